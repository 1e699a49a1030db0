#include "processing/calibration/rig_tie_points.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>

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

}  // namespace

// A pair of the panorama: its left view, and an even sample of its points (candidates_per_tie
// times the tie points wanted): predicting every point of a pair into every pose would cost
// more than the matching.
struct RigTiePair {
  double pan_deg = 0.0, tilt_deg = 0.0;
  View view;
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Matrix3d> covariances;
};

namespace {

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
// least-squares matching, whose fit gives the position and its sigma.
std::optional<LsmResult> Find(const View& from, const View& to, const Candidate& c,
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
  return r;
}

RigTiePair MakeTiePair(const Calibration& calibration, const StereoPairImages& pair,
                       const MatchedPair& matched, const RigTiePointOptions& o) {
  constexpr size_t kCandidatesPerTie = 10;
  RigTiePair t;
  t.pan_deg = pair.pan_deg;
  t.tilt_deg = pair.tilt_deg;
  t.view.image = AsFloat(pair.left);
  t.view.gradients = ComputeGradients(t.view.image);
  t.view.camera_from_l =
      calibration.LFromCamera(Side::kLeft, pair.pan_deg, pair.tilt_deg).inverse();
  const size_t sample =
      std::max<size_t>(1, matched.cloud.size() / (kCandidatesPerTie * o.max_per_neighbour));
  for (size_t i = 0; i < matched.cloud.size(); i += sample) {
    t.points.push_back(matched.cloud[i].position_m);
    t.covariances.push_back(matched.cloud[i].covariance_m2.cast<double>());
  }
  return t;
}

// Pair `from`'s points found in pair `to`'s left image: points and observations indexed within
// `out`, the poses being 0 (from) and 1 (to).
void TiePointsBetween(const Calibration& calibration, const CameraModel& left,
                      const CameraModel& right, const RigTiePair& from, const RigTiePair& to,
                      const RigTiePointOptions& o, RigAdjustmentInput* out) {
  std::vector<Candidate> candidates;
  std::vector<Eigen::Matrix3d> covariances;
  for (size_t i = 0; i < from.points.size(); ++i)
    if (auto c = Predict(left, from.view, to.view, from.points[i]);
        c && left.InImage(c->predicted)) {
      candidates.push_back(*c);
      covariances.push_back(from.covariances[i]);
    }
  if (static_cast<int>(candidates.size()) < o.min_candidates) return;
  const size_t step = std::max<size_t>(1, candidates.size() / o.max_per_neighbour);
  const Eigen::Isometry3d right_from_l =
      calibration.LFromCamera(Side::kRight, from.pan_deg, from.tilt_deg).inverse();
  for (size_t i = 0; i < candidates.size(); i += step) {
    const Candidate& c = candidates[i];
    const std::optional<LsmResult> found = Find(from.view, to.view, c, o);
    Eigen::Vector2d in_right;
    if (!found || !right.Project(right_from_l * c.point, &in_right)) continue;
    const int point = static_cast<int>(out->points.size());
    out->points.push_back(c.point);
    out->point_covariance_m2.push_back(covariances[i]);
    out->observations.push_back({0, Side::kLeft, point, c.centre});
    out->observations.push_back({0, Side::kRight, point, in_right, true});
    // The fit's sigma per coordinate (the RMS of its two).
    const double sigma_px = std::hypot(found->sigma_x_px, found->sigma_y_px) / std::sqrt(2.0);
    out->observations.push_back({1, Side::kLeft, point, found->position_px, false, sigma_px});
  }
}

}  // namespace

RigTieFinder::RigTieFinder(const Calibration& calibration, const RigTiePointOptions& options)
    : calibration_(calibration), options_(options) {}

RigTieFinder::~RigTieFinder() = default;

bool RigTieFinder::Has(int index, double pan_deg, double tilt_deg) const {
  const auto p = pairs_.find(index);
  return p != pairs_.end() && p->second->pan_deg == pan_deg && p->second->tilt_deg == tilt_deg;
}

void RigTieFinder::Add(const std::vector<StereoPairImages>& pairs,
                       const std::vector<MatchedPair>& matched) {
  std::vector<std::shared_ptr<RigTiePair>> made(pairs.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(pairs.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i)
      made[i] =
          std::make_shared<RigTiePair>(MakeTiePair(calibration_, pairs[i], matched[i], options_));
  });
  std::set<int> added;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const int index = pairs[i].index;
    pairs_[index] = made[i];
    added.insert(index);
    // A pair added again (captured again) replaces its tie points.
    std::erase_if(blocks_,
                  [&](const auto& b) { return b.first.first == index || b.first.second == index; });
  }
  std::vector<std::pair<int, int>> tasks;
  for (const auto& [k, from] : pairs_)
    for (const auto& [j, to] : pairs_)
      if (k != j && (added.count(k) || added.count(j))) tasks.emplace_back(k, j);
  std::vector<RigAdjustmentInput> found(tasks.size());
  const CameraModel left(calibration_.rig.left), right(calibration_.rig.right);
  cv::parallel_for_(cv::Range(0, static_cast<int>(tasks.size())), [&](const cv::Range& range) {
    for (int t = range.start; t < range.end; ++t)
      TiePointsBetween(calibration_, left, right, *pairs_.at(tasks[t].first),
                       *pairs_.at(tasks[t].second), options_, &found[t]);
  });
  for (size_t t = 0; t < tasks.size(); ++t)
    if (!found[t].points.empty()) blocks_[tasks[t]] = std::move(found[t]);
}

RigAdjustmentInput RigTieFinder::Input(const std::vector<int>& order) const {
  RigAdjustmentInput input;
  input.calibration = calibration_;
  input.stations = input.Stations();  // one, levelled as the calibration
  for (int index : order) {
    const RigTiePair& p = *pairs_.at(index);
    input.poses.push_back({p.pan_deg, p.tilt_deg});
  }
  for (size_t k = 0; k < order.size(); ++k)
    for (size_t j = 0; j < order.size(); ++j) {
      const auto block = blocks_.find({order[k], order[j]});
      if (block == blocks_.end()) continue;
      const RigAdjustmentInput& f = block->second;
      const int offset = static_cast<int>(input.points.size());
      input.points.insert(input.points.end(), f.points.begin(), f.points.end());
      input.point_covariance_m2.insert(input.point_covariance_m2.end(),
                                       f.point_covariance_m2.begin(), f.point_covariance_m2.end());
      for (RigTieObservation t : f.observations) {
        t.point += offset;
        t.pose = static_cast<int>(t.pose == 0 ? k : j);
        input.observations.push_back(t);
      }
    }
  return input;
}

RigAdjustmentInput FindRigTiePoints(const Calibration& calibration,
                                    const std::vector<StereoPairImages>& pairs,
                                    const std::vector<MatchedPair>& matched,
                                    const RigTiePointOptions& o) {
  RigTieFinder finder(calibration, o);
  finder.Add(pairs, matched);
  std::vector<int> order;
  for (const StereoPairImages& p : pairs) order.push_back(p.index);
  return finder.Input(order);
}

}  // namespace ts
