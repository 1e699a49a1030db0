#include "sim/calibration_field.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "processing/geometry/rotation.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "sim/calibration_views.h"
#include "sim/noise.h"

namespace ts::sim {
namespace {

// The black square around a disc, in disc diameters (half its side).
constexpr double kSurroundHalfSide = 1.25;
// Targets closer than this (seen from the pillar) would share a search window.
constexpr double kMinSeparationDeg = 2.0;

// Targets in the station frame L: azimuth clockwise from +Y, elevation, distance.
std::vector<Eigen::Vector3d> PlaceTargets(std::mt19937_64& rng, const FieldSessionOptions& o) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> directions, points;
  for (int attempt = 0; attempt < 100 * o.targets && static_cast<int>(points.size()) < o.targets;
       ++attempt) {
    const double azimuth = RadFromDeg(o.azimuth_span_deg * (u(rng) - 0.5));
    const double elevation = RadFromDeg(o.elevation_span_deg * (u(rng) - 0.5));
    const Eigen::Vector3d d(std::sin(azimuth) * std::cos(elevation),
                            std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
    bool free = true;
    for (const Eigen::Vector3d& other : directions)
      free = free && d.dot(other) < std::cos(RadFromDeg(kMinSeparationDeg));
    if (!free) continue;
    directions.push_back(d);
    points.push_back(d * (o.min_distance_m + (o.max_distance_m - o.min_distance_m) * u(rng)));
  }
  return points;
}

// A target's radiance where a ray from the camera meets its plane (it faces the pillar).
struct TargetInCamera {
  Eigen::Vector3d centre, normal, across, up;  // camera frame
  double diameter;
  float Radiance(const Eigen::Vector3d& ray) const {
    const double denominator = ray.dot(normal);
    if (std::abs(denominator) < 1e-12) return kTargetBackground;
    const double t = centre.dot(normal) / denominator;
    if (t <= 0.0) return kTargetBackground;
    const Eigen::Vector3d local = t * ray - centre;
    const double x = local.dot(across), y = local.dot(up);
    if (x * x + y * y <= 0.25 * diameter * diameter) return kTargetWhite;
    const double half = kSurroundHalfSide * diameter;
    return std::abs(x) <= half && std::abs(y) <= half ? kTargetBlack : kTargetBackground;
  }
};

TargetInCamera Place(const FieldTarget& target, const Eigen::Isometry3d& station_from_field,
                     const Eigen::Isometry3d& camera_from_station) {
  const Eigen::Vector3d in_station = station_from_field * target.position_m;
  const Eigen::Vector3d normal = -in_station.normalized();
  const Eigen::Vector3d across = normal.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d up = across.cross(normal);
  const Eigen::Matrix3d r = camera_from_station.linear();
  return {camera_from_station * in_station, r * normal, r * across, r * up, target.diameter_m};
}

// The pixels the target's square can cover, or an empty rectangle.
cv::Rect TargetExtent(const CameraModel& model, const TargetInCamera& t) {
  const double half = kSurroundHalfSide * t.diameter;
  Eigen::Vector2d low = Eigen::Vector2d::Constant(1e300), high = -low;
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector3d p =
        t.centre + (corner & 1 ? half : -half) * t.across + (corner & 2 ? half : -half) * t.up;
    Eigen::Vector2d pixel;
    if (p.z() <= 0.0 || !model.Project(p, &pixel)) return {};
    low = low.cwiseMin(pixel);
    high = high.cwiseMax(pixel);
  }
  const CameraIntrinsics& c = model.intrinsics();
  const cv::Rect extent(static_cast<int>(std::floor(low.x())) - 2,
                        static_cast<int>(std::floor(low.y())) - 2,
                        static_cast<int>(std::ceil(high.x() - low.x())) + 5,
                        static_cast<int>(std::ceil(high.y() - low.y())) + 5);
  return extent & cv::Rect(0, 0, c.width_px, c.height_px);
}

Eigen::Isometry3d CameraFromStation(const SimRig& rig, Side side, const StagePose& pose) {
  return rig.truth.LFromCamera(side, pose.pan_deg, pose.tilt_deg).inverse();
}

// Hand marks in a left image: the targets nearest to the frame's centre and the centres of
// its quadrants, their true pixels with a hand's error.
ImageMarks MarkView(const SimRig& rig, const FieldSession& s, int k, uint64_t seed,
                    const FieldSessionOptions& o) {
  const CameraIntrinsics& camera = rig.truth.rig.left;
  const CameraModel model(camera);
  const Eigen::Isometry3d camera_from_field =
      CameraFromStation(rig, Side::kLeft, s.poses[k]) * s.field_from_station.inverse();
  std::vector<std::pair<int, Eigen::Vector2d>> visible;
  for (size_t i = 0; i < s.truth.targets.size(); ++i) {
    const Eigen::Vector3d p = camera_from_field * s.truth.targets[i].position_m;
    Eigen::Vector2d pixel;
    if (p.z() > 0.0 && model.Project(p, &pixel) && pixel.x() > 40 && pixel.y() > 40 &&
        pixel.x() < camera.width_px - 40 && pixel.y() < camera.height_px - 40)
      visible.emplace_back(static_cast<int>(i), pixel);
  }
  ImageMarks marks;
  char name[32];
  std::snprintf(name, sizeof(name), "left/%02d.png", k + 1);
  marks.image = name;
  const double anchors[5][2] = {{0.5, 0.5}, {0.25, 0.25}, {0.75, 0.25}, {0.25, 0.75}, {0.75, 0.75}};
  std::vector<int> taken;
  for (int a = 0; a < o.marks_per_view; ++a) {
    const Eigen::Vector2d anchor(anchors[a % 5][0] * camera.width_px,
                                 anchors[a % 5][1] * camera.height_px);
    int best = -1;
    for (size_t v = 0; v < visible.size(); ++v)
      if (std::find(taken.begin(), taken.end(), v) == taken.end() &&
          (best < 0 ||
           (visible[v].second - anchor).norm() < (visible[best].second - anchor).norm()))
        best = static_cast<int>(v);
    if (best < 0) break;
    taken.push_back(best);
    const Eigen::Vector2d error(HashUnit(seed, k, a, 1), HashUnit(seed, k, a, 2));
    marks.marks.push_back({s.truth.targets[visible[best].first].id,
                           visible[best].second + o.mark_sigma_px * std::sqrt(3.0) * error});
  }
  return marks;
}

}  // namespace

bool FieldSessionOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (min_distance_m > max_distance_m) {
    if (why) *why = "min_distance_m must not exceed max_distance_m";
    return false;
  }
  return true;
}

FieldSession PlanFieldSession(const SimRig& rig, uint64_t seed, const FieldSessionOptions& o) {
  std::mt19937_64 rng(Hash(seed, 0xF1E1D, 0x5E55));
  std::normal_distribution<double> noise(0.0, 1.0);
  FieldSession s;
  // The field's own frame: survey coordinates, turned against the station's.
  s.field_from_station.linear() =
      Eigen::AngleAxisd(RadFromDeg(35.0), Eigen::Vector3d::UnitZ()).matrix();
  s.field_from_station.translation() = Eigen::Vector3d(512.0, 208.0, 31.0);
  const std::vector<Eigen::Vector3d> points = PlaceTargets(rng, o);
  for (size_t i = 0; i < points.size(); ++i) {
    FieldTarget t;
    t.id = 101 + static_cast<int>(i);
    t.position_m = s.field_from_station * points[i];
    t.sigma_m = o.survey_sigma_m;
    t.diameter_m = std::round(o.diameter_per_m * points[i].norm() * 1000.0) / 1000.0;
    s.truth.targets.push_back(t);
    t.position_m += o.survey_sigma_m * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    s.surveyed.targets.push_back(t);
  }
  s.poses = MakeFieldPoseGrid(o.poses);
  for (size_t k = 0; k < s.poses.size(); ++k)
    s.marks.push_back(MarkView(rig, s, static_cast<int>(k), seed, o));
  return s;
}

cv::Mat RenderFieldView(const SimRig& rig, const FieldSession& s, Side side, const StagePose& pose,
                        int supersampling) {
  const CameraIntrinsics& camera = side == Side::kLeft ? rig.truth.rig.left : rig.truth.rig.right;
  const CameraModel model(camera);
  const Eigen::Isometry3d camera_from_station = CameraFromStation(rig, side, pose);
  const Eigen::Isometry3d station_from_field = s.field_from_station.inverse();
  cv::Mat radiance(camera.height_px, camera.width_px, CV_32FC1, cv::Scalar(kTargetBackground));
  const int n = supersampling;
  cv::parallel_for_(
      cv::Range(0, static_cast<int>(s.truth.targets.size())), [&](const cv::Range& r) {
        for (int i = r.start; i < r.end; ++i) {
          const TargetInCamera t =
              Place(s.truth.targets[i], station_from_field, camera_from_station);
          const cv::Rect extent = TargetExtent(model, t);
          for (int y = extent.y; y < extent.y + extent.height; ++y)
            for (int x = extent.x; x < extent.x + extent.width; ++x) {
              double sum = 0.0;
              for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a)
                  sum += t.Radiance(
                      model.RayFromPixel({x - 0.5 + (a + 0.5) / n, y - 0.5 + (b + 0.5) / n}));
              radiance.at<float>(y, x) = static_cast<float>(sum / (n * n));
            }
        }
      });
  return radiance;
}

cv::Mat ExposeFieldView(const SimRig& rig, const FieldSession& s, Side side, int pose,
                        uint64_t seed, const FieldSessionOptions& o) {
  const CameraIntrinsics& camera = side == Side::kLeft ? rig.truth.rig.left : rig.truth.rig.right;
  return ExposeImage(RenderFieldView(rig, s, side, s.poses[pose], o.supersampling), camera,
                     rig.sensor(side), o.exposure_us, 0.0, PixelFormat::kMono8,
                     Hash(seed, pose, 0xF1E1D, side == Side::kLeft));
}

Status WriteFieldSession(const SimRig& rig, uint64_t seed, const FieldSessionOptions& o,
                         const std::string& dir, const std::string& truth_dir) {
  namespace fs = std::filesystem;
  std::string why;
  if (!o.Check(&why)) return Error{"field session: " + why};
  std::error_code ec;
  for (const fs::path& d : {fs::path(dir) / "left", fs::path(dir) / "right", fs::path(truth_dir)})
    if (fs::create_directories(d, ec); ec) return Error{d.string() + ": " + ec.message()};
  const FieldSession s = PlanFieldSession(rig, seed, o);
  nlohmann::json poses = nlohmann::json::array();
  for (size_t k = 0; k < s.poses.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof(name), "%02d.png", static_cast<int>(k) + 1);
    for (Side side : {Side::kLeft, Side::kRight}) {
      const cv::Mat image = ExposeFieldView(rig, s, side, static_cast<int>(k), seed, o);
      const fs::path file = fs::path(dir) / SideName(side) / name;
      if (!cv::imwrite(file.string(), image)) return Error{file.string() + ": cannot write"};
    }
    poses.push_back(
        {{"image", name}, {"pan_deg", s.poses[k].pan_deg}, {"tilt_deg", s.poses[k].tilt_deg}});
  }
  const auto in = [&](const char* name) { return (fs::path(dir) / name).string(); };
  if (Status st = SaveControlField(s.surveyed, in("field.yaml")); !st) return st;
  if (Status st = SaveTargetMarks(s.marks, in("marks.yaml")); !st) return st;
  if (Status st = SaveCalibrationYaml(rig.nominal, in("design.yaml")); !st) return st;
  const nlohmann::json description = {
      {"targets", s.surveyed.targets.size()},
      {"stage_poses", poses},
      {"calibrate", "topostation calibrate stereo --left '" + dir + "/left/*.png' --right '" + dir +
                        "/right/*.png' --control-field " + in("field.yaml") + " --marks " +
                        in("marks.yaml") + " --start " + in("design.yaml") + " --out CAL.yaml"}};
  if (Status st = WriteFileAtomically(in("session.json"), description.dump(2) + "\n"); !st)
    return st;
  if (Status st =
          SaveCalibrationYaml(rig.truth, (fs::path(truth_dir) / "calibration.yaml").string());
      !st)
    return st;
  return SaveControlField(s.truth, (fs::path(truth_dir) / "field.yaml").string());
}

}  // namespace ts::sim
