#include "processing/matching/terrain_above_view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "processing/geometry/rotation.h"
#include "processing/matching/enhance.h"
#include "processing/matching/pyramid_ncc.h"
#include "processing/matching/triangulation.h"

namespace ts {

bool TerrainAboveOptions::Check(std::string* why) const {
  std::string err;
  if (!(far_range_m > 0.0))
    err = "far_range_m must be positive";
  else if (!(band_fraction > 0.0 && band_fraction <= 0.5))
    err = "band_fraction must be in (0, 0.5]";
  else if (!(max_inclination_deg > 0.0 && max_inclination_deg < 90.0))
    err = "max_inclination_deg must be in (0, 90)";
  else if (!(min_share > 0.0 && min_share <= 1.0))
    err = "min_share must be in (0, 1]";
  else if (level < 0 || level > 4)
    err = "level must be in [0, 4]";
  else if (!(min_depth_m > 0.0 && max_depth_m > min_depth_m))
    err = "need 0 < min_depth_m < max_depth_m";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

TerrainAboveVerdict JudgeTerrainAboveView(const Calibration& cal, const Rectification& r,
                                          const cv::Mat& left_raw, const cv::Mat& right_raw,
                                          const StagePose& pose, const TerrainAboveOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("terrain above view: " + why);
  cv::Mat left_rect, right_rect;
  RectifyPair(r, left_raw, right_raw, &left_rect, &right_rect);
  const EnhanceOptions enhance;
  const cv::Mat left = Enhance(left_rect, enhance), right = Enhance(right_rect, enhance);
  const DisparityMap map =
      MatchPyramid(left, right, r.MinDisparityPx(o.max_depth_m), r.MaxDisparityPx(o.min_depth_m),
                   o.level, PyramidNccOptions{});

  const int scale = 1 << map.level;
  const Eigen::Isometry3d L_from_left = cal.LFromCamera(Side::kLeft, pose.pan_deg, pose.tilt_deg);
  const Eigen::Matrix3d rotation = L_from_left.linear() * r.left_from_rect;
  // A map pixel's point in L (intersected as a full-resolution match), if it has a disparity
  // worth believing.
  auto point = [&](int x, int y, Eigen::Vector3d* p) {
    const int d = map.disparity.at<int16_t>(y, x);
    if (d <= 0 || map.score.at<float>(y, x) < o.min_ncc) return false;
    StereoMatch match;
    match.left_px = {(x + 0.5) * scale - 0.5, (y + 0.5) * scale - 0.5};
    match.disparity_px = d * scale;
    Eigen::Vector3d in_rect;
    Eigen::Matrix3d covariance;
    if (!TriangulateRectified(r, match, &in_rect, &covariance)) return false;
    *p = L_from_left.translation() + rotation * in_rect;
    return true;
  };
  const int band = std::max(2, static_cast<int>(std::lround(o.band_fraction * map.disparity.rows)));
  const double steepest = std::tan(RadFromDeg(o.max_inclination_deg));
  int columns = 0, terrain = 0;
  for (int x = 0; x < map.disparity.cols; ++x) {
    // Columns outside the original image at the band's rows do not count.
    const int u = std::min(static_cast<int>((x + 0.5) * scale), r.left_map_x.cols - 1);
    const int v = std::min(static_cast<int>(band * scale / 2), r.left_map_x.rows - 1);
    if (r.left_map_x.at<float>(v, u) < 0.0f) continue;
    ++columns;
    Eigen::Vector3d top = Eigen::Vector3d::Zero(), bottom = Eigen::Vector3d::Zero();
    int top_row = -1, bottom_row = -1;
    for (int y = 0; y < band; ++y)
      if (point(x, y, &top)) {
        top_row = y;
        break;
      }
    for (int y = band - 1; y > top_row; --y)
      if (point(x, y, &bottom)) {
        bottom_row = y;
        break;
      }
    if (top_row < 0 || bottom_row - top_row < band / 2) continue;
    const double top_range = top.head<2>().norm(), bottom_range = bottom.head<2>().norm();
    if (top_range < o.far_range_m && top_range > bottom_range &&
        top.z() - bottom.z() < steepest * (top_range - bottom_range))
      ++terrain;
  }
  TerrainAboveVerdict verdict;
  verdict.share = columns > 0 ? static_cast<double>(terrain) / columns : 0.0;
  verdict.terrain_above = verdict.share >= o.min_share;
  return verdict;
}

bool ExtendPlanUpwards(const Calibration& cal, const Rectification& r, const cv::Mat& left,
                       const cv::Mat& right, const StagePose& taken, const StagePose& reached,
                       const CapturePlanOptions& o, std::vector<StagePose>* plan) {
  StagePose upper;
  if (!o.upper_poses || !UpperPose(cal, taken, o, &upper)) return false;
  for (const StagePose& p : *plan)  // a pair taken again (resume) already has its upper pose
    if (std::abs(p.pan_deg - upper.pan_deg) < 1e-6 && std::abs(p.tilt_deg - upper.tilt_deg) < 1e-6)
      return false;
  TerrainAboveOptions judge;
  judge.far_range_m = o.far_range_m;
  if (!JudgeTerrainAboveView(cal, r, left, right, reached, judge).terrain_above) return false;
  plan->push_back(upper);
  return true;
}

}  // namespace ts
