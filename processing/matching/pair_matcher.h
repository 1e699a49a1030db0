#pragma once
// Dense matching of one rectified stereo pair (seed 003 sec. 4; seed 002's two-way matching):
//   enhance (Gaussian + Wallis) -> Förstner points on the left -> NCC along the same row of
//   the right, over the disparities of a depth range -> least-squares matching (on the
//   Gaussian-only images: see pair_matcher.cc) for the sub-pixel disparity and its sigma ->
//   right-to-left NCC must find the way back (consistency).
// Coordinates are rectified pixels (rectification.h); depth = f B / disparity.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "processing/matching/enhance.h"
#include "processing/matching/forstner.h"
#include "processing/matching/lsm.h"
#include "processing/matching/rectification.h"

namespace ts {

struct PairMatchOptions {
  EnhanceOptions enhance;
  ForstnerOptions interest;
  int ncc_half_window_px = 5;
  double min_ncc = 0.8;
  double min_depth_m = 1.5;  // nearest ground the rig can see
  double max_depth_m = 150.0;
  // An explicit disparity range instead of the depth range (both >= 0, max > min), e.g. for
  // a stereo pair without a known geometry; -1 = derive it from the depths.
  int min_disparity_px = -1;
  int max_disparity_px = -1;
  // 21 x 21 LSM windows: on the simulated hills pair the disparity error is noise-limited and
  // falls with the window (half 5 / 7 / 10 / 13: median 0.178 / 0.130 / 0.103 / 0.093 px).
  LsmOptions lsm = [] {
    LsmOptions o;
    o.half_window_px = 10;
    return o;
  }();
  int max_consistency_px = 1;  // right-to-left integer disparity may differ this much
  bool Check(std::string* why) const;
};

struct StereoMatch {
  Eigen::Vector2d left_px{0, 0};   // rectified left
  Eigen::Vector2d right_px{0, 0};  // rectified right (LSM)
  double disparity_px = 0.0;
  double sigma_disparity_px = 0.0;
  double correlation = 0.0;
};

struct PairMatchSummary {
  int interest_points = 0;
  int ncc_accepted = 0;
  int lsm_accepted = 0;
  int consistent = 0;
};

std::vector<StereoMatch> MatchRectifiedPair(const Rectification& rectification,
                                            const cv::Mat& left_rect, const cv::Mat& right_rect,
                                            const PairMatchOptions& options,
                                            PairMatchSummary* summary = nullptr);

}  // namespace ts
