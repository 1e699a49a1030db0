#include "processing/calibration/rig_tie_points.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "processing/geometry/camera_model.h"

namespace ts {
namespace {

cv::Mat AsFloat(const cv::Mat& image) {
  cv::Mat f;
  image.convertTo(f, CV_32F);
  return f;
}

// A view of the panorama: its image, gradients and pose in L by the calibration.
struct View {
  cv::Mat image;
  ImageGradients gradients;
  Eigen::Isometry3d camera_from_l;
};

struct Candidate {
  Eigen::Vector2d centre;     // the template's centre in the pair's left image (integer)
  Eigen::Vector3d point;      // in L, on the ray through `centre`
  Eigen::Vector2d predicted;  // in the neighbour's left image
  Eigen::Matrix2d shape;      // d predicted / d centre
};

// A point of the pair, moved onto the ray through the nearest pixel centre at its distance,
// and its predicted place and local mapping in the neighbour.
std::optional<Candidate> Predict(const CameraModel& model, const View& from, const View& to,
                                 const Eigen::Vector3d& point_l) {
  const Eigen::Vector3d in_from = from.camera_from_l * point_l;
  Eigen::Vector2d pixel;
  if (!model.Project(in_from, &pixel)) return std::nullopt;
  const Eigen::Vector2d centre(std::round(pixel.x()), std::round(pixel.y()));
  const double distance = in_from.norm();
  const Eigen::Isometry3d l_from_camera = from.camera_from_l.inverse();
  const auto at = [&](const Eigen::Vector2d& p, Eigen::Vector2d* out) {
    return model.Project(
        to.camera_from_l * (l_from_camera * (model.RayFromPixel(p).normalized() * distance)), out);
  };
  Candidate c;
  c.centre = centre;
  c.point = l_from_camera * (model.RayFromPixel(centre).normalized() * distance);
  Eigen::Vector2d dx, dy;
  if (!at(centre, &c.predicted) || !at(centre + Eigen::Vector2d(1, 0), &dx) ||
      !at(centre + Eigen::Vector2d(0, 1), &dy))
    return std::nullopt;
  c.shape.col(0) = dx - c.predicted;
  c.shape.col(1) = dy - c.predicted;
  return c;
}

// The candidate found in the neighbour: NCC of the warped window about the prediction, then
// least-squares matching.
std::optional<Eigen::Vector2d> Find(const View& from, const View& to, const Candidate& c,
                                    const RigTiePointOptions& o) {
  const int h = o.half_window_px, s = static_cast<int>(std::ceil(o.search_px));
  const cv::Rect search(static_cast<int>(std::round(c.predicted.x())) - h - s,
                        static_cast<int>(std::round(c.predicted.y())) - h - s, 2 * (h + s) + 1,
                        2 * (h + s) + 1);
  if ((search & cv::Rect(0, 0, to.image.cols, to.image.rows)) != search) return std::nullopt;
  // The window as the neighbour would see it: template pixel u <- from's centre + A^-1 u.
  const Eigen::Matrix2d inverse = c.shape.inverse();
  const cv::Mat warp = (cv::Mat_<double>(2, 3) << inverse(0, 0), inverse(0, 1),
                        c.centre.x() - inverse(0, 0) * h - inverse(0, 1) * h, inverse(1, 0),
                        inverse(1, 1), c.centre.y() - inverse(1, 0) * h - inverse(1, 1) * h);
  cv::Mat window;
  cv::warpAffine(from.image, window, warp, cv::Size(2 * h + 1, 2 * h + 1),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP);
  cv::Mat score;
  cv::matchTemplate(to.image(search), window, score, cv::TM_CCOEFF_NORMED);
  double best = 0.0;
  cv::Point peak;
  cv::minMaxLoc(score, nullptr, &best, nullptr, &peak);
  if (!(best >= o.min_correlation)) return std::nullopt;
  const Eigen::Vector2d start(search.x + peak.x + h, search.y + peak.y + h);
  LsmOptions lsm;
  lsm.half_window_px = h;
  lsm.min_correlation = o.min_correlation;
  const LsmResult r =
      MatchLsm(from.image, from.gradients,
               cv::Point(static_cast<int>(c.centre.x()), static_cast<int>(c.centre.y())), to.image,
               start, lsm, &c.shape);
  if (!r.ok) return std::nullopt;
  return r.position_px;
}

// Pair k's points found in pose j's left image, added to `out` (points and observations indexed
// within it). Predicting every point of a pair into every pose would cost more than the
// matching: an even sample of candidates_per_tie times the tie points wanted is predicted.
void TiePointsBetween(const Calibration& calibration, const CameraModel& left,
                      const CameraModel& right, const StereoPairImages& pair,
                      const MatchedPair& matched, const std::vector<View>& views, int k, int j,
                      const RigTiePointOptions& o, RigAdjustmentInput* out) {
  constexpr size_t kCandidatesPerTie = 10;
  const size_t sample =
      std::max<size_t>(1, matched.cloud.size() / (kCandidatesPerTie * o.max_per_neighbour));
  std::vector<Candidate> candidates;
  std::vector<Eigen::Matrix3d> covariances;
  for (size_t i = 0; i < matched.cloud.size(); i += sample) {
    const CloudPoint& p = matched.cloud[i];
    if (auto c = Predict(left, views[k], views[j], p.position_m); c && left.InImage(c->predicted)) {
      candidates.push_back(*c);
      covariances.push_back(p.covariance_m2.cast<double>());
    }
  }
  if (static_cast<int>(candidates.size()) < o.min_candidates) return;
  const size_t step = std::max<size_t>(1, candidates.size() / o.max_per_neighbour);
  const Eigen::Isometry3d right_from_l =
      calibration.LFromCamera(Side::kRight, pair.pan_deg, pair.tilt_deg).inverse();
  for (size_t i = 0; i < candidates.size(); i += step) {
    const Candidate& c = candidates[i];
    const std::optional<Eigen::Vector2d> found = Find(views[k], views[j], c, o);
    Eigen::Vector2d in_right;
    if (!found || !right.Project(right_from_l * c.point, &in_right)) continue;
    const int point = static_cast<int>(out->points.size());
    out->points.push_back(c.point);
    out->point_covariance_m2.push_back(covariances[i]);
    out->observations.push_back({k, Side::kLeft, point, c.centre});
    out->observations.push_back({k, Side::kRight, point, in_right, true});
    out->observations.push_back({j, Side::kLeft, point, *found});
  }
}

}  // namespace

RigAdjustmentInput FindRigTiePoints(const Calibration& calibration,
                                    const std::vector<StereoPairImages>& pairs,
                                    const std::vector<MatchedPair>& matched,
                                    const RigTiePointOptions& o) {
  RigAdjustmentInput input;
  input.calibration = calibration;
  input.stations = input.Stations();  // one, levelled as the calibration
  std::vector<View> views;
  for (const StereoPairImages& pair : pairs) {
    input.poses.push_back({pair.pan_deg, pair.tilt_deg});
    View v;
    v.image = AsFloat(pair.left);
    v.gradients = ComputeGradients(v.image);
    v.camera_from_l = calibration.LFromCamera(Side::kLeft, pair.pan_deg, pair.tilt_deg).inverse();
    views.push_back(std::move(v));
  }
  const CameraModel left(calibration.rig.left), right(calibration.rig.right);
  // Each pair's tie points with every other pose, found in parallel (one pair per task) and
  // gathered in pair order, so that the result does not depend on the scheduling.
  std::vector<RigAdjustmentInput> found(pairs.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(pairs.size())), [&](const cv::Range& range) {
    for (int k = range.start; k < range.end; ++k)
      for (size_t j = 0; j < pairs.size(); ++j)
        if (static_cast<int>(j) != k)
          TiePointsBetween(calibration, left, right, pairs[k], matched[k], views, k,
                           static_cast<int>(j), o, &found[k]);
  });
  for (const RigAdjustmentInput& f : found) {
    const int offset = static_cast<int>(input.points.size());
    input.points.insert(input.points.end(), f.points.begin(), f.points.end());
    input.point_covariance_m2.insert(input.point_covariance_m2.end(), f.point_covariance_m2.begin(),
                                     f.point_covariance_m2.end());
    for (RigTieObservation t : f.observations) {
      t.point += offset;
      input.observations.push_back(t);
    }
  }
  return input;
}

}  // namespace ts
