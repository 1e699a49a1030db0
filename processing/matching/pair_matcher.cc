#include "processing/matching/pair_matcher.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ts {

bool PairMatchOptions::Check(std::string* why) const {
  std::string err;
  if (!enhance.Check(&err) || !interest.Check(&err) || !lsm.Check(&err)) {
  } else if (ncc_half_window_px < 2) {
    err = "ncc_half_window_px must be at least 2";
  } else if (!(min_depth_m > 0.0 && max_depth_m > min_depth_m)) {
    err = "need 0 < min_depth_m < max_depth_m";
  } else if ((min_disparity_px >= 0) != (max_disparity_px >= 0) ||
             (max_disparity_px >= 0 && max_disparity_px <= min_disparity_px)) {
    err = "give both min_disparity_px and max_disparity_px, with max > min";
  } else if (max_consistency_px < 0) {
    err = "max_consistency_px must not be negative";
  }
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

// Best integer disparity of a window centred at (u, v) of `from` along row v of `to`, with
// the candidate position to = u - sign * d for d in [d_min, d_max]; -1 if none is found.
int SearchRow(const cv::Mat& from, const cv::Mat& to, int u, int v, int h, int d_min, int d_max,
              int sign, double min_ncc, double* score) {
  const int lo = sign > 0 ? u - d_max : u + d_min;
  const int hi = sign > 0 ? u - d_min : u + d_max;
  const int x0 = std::max(h, lo), x1 = std::min(to.cols - h - 1, hi);
  if (x1 < x0 || v < h || v + h >= from.rows || u < h || u + h >= from.cols) return -1;
  const cv::Mat templ = from(cv::Rect(u - h, v - h, 2 * h + 1, 2 * h + 1));
  const cv::Mat strip = to(cv::Rect(x0 - h, v - h, x1 - x0 + 2 * h + 1, 2 * h + 1));
  cv::Mat ncc;
  cv::matchTemplate(strip, templ, ncc, cv::TM_CCOEFF_NORMED);
  double best;
  cv::Point at;
  cv::minMaxLoc(ncc, nullptr, &best, nullptr, &at);
  if (!(best >= min_ncc)) return -1;
  *score = best;
  return sign > 0 ? u - (x0 + at.x) : (x0 + at.x) - u;
}

}  // namespace

std::vector<StereoMatch> MatchRectifiedPair(const Rectification& r, const cv::Mat& left_rect,
                                            const cv::Mat& right_rect, const PairMatchOptions& o,
                                            PairMatchSummary* summary) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("pair matching: " + why);
  PairMatchSummary s;
  // Wallis for finding points and searching; not for least-squares matching: its local gain
  // varies across a window differently in the two views where perspective differs (near
  // ground), a ramp LSM's linear radiometry cannot absorb (measured: -0.33 px bias below 8 m).
  const cv::Mat left = Enhance(left_rect, o.enhance), right = Enhance(right_rect, o.enhance);
  EnhanceOptions smooth_only = o.enhance;
  smooth_only.wallis = false;
  const cv::Mat lsm_left = Enhance(left_rect, smooth_only);
  const cv::Mat lsm_right = Enhance(right_rect, smooth_only);
  const SearchGradients gradients = ComputeSearchGradients(lsm_right);
  const std::vector<InterestPoint> points = DetectForstner(left, o.interest);
  s.interest_points = static_cast<int>(points.size());
  const double fb = r.focal_px * r.baseline_m;
  const bool explicit_range = o.max_disparity_px >= 0;
  const int d_min = explicit_range ? o.min_disparity_px
                                   : std::max(0, static_cast<int>(std::floor(fb / o.max_depth_m)));
  const int d_max =
      explicit_range ? o.max_disparity_px : static_cast<int>(std::ceil(fb / o.min_depth_m));
  const int h = o.ncc_half_window_px;
  std::vector<StereoMatch> matches;
  for (const InterestPoint& p : points) {
    const int u = static_cast<int>(std::lround(p.position_px.x()));
    const int v = static_cast<int>(std::lround(p.position_px.y()));
    double ncc = 0.0;
    const int d = SearchRow(left, right, u, v, h, d_min, d_max, +1, o.min_ncc, &ncc);
    if (d < 0) continue;
    ++s.ncc_accepted;
    // The template sits on whole pixels: resampling it would smooth it unlike the search
    // window and bias the fit.
    const Eigen::Vector2d at(u, v);
    const LsmResult lsm =
        MatchLsm(lsm_left, at, lsm_right, gradients, at - Eigen::Vector2d(d, 0.0), o.lsm);
    if (!lsm.ok) continue;
    ++s.lsm_accepted;
    // Two-way: from the matched right position back along the row must come home.
    double back_ncc = 0.0;
    const int ur = static_cast<int>(std::lround(lsm.position_px.x()));
    const int back = SearchRow(right, left, ur, v, h, d_min, d_max, -1, o.min_ncc, &back_ncc);
    const double disparity = at.x() - lsm.position_px.x();
    if (back < 0 || std::abs(back - disparity) > o.max_consistency_px + 0.5) continue;
    ++s.consistent;
    matches.push_back({at, lsm.position_px, disparity, lsm.sigma_x_px, lsm.correlation});
  }
  if (summary) *summary = s;
  return matches;
}

}  // namespace ts
