#pragma once
// Matching of one rectified stereo pair (seed 003 sec. 4; seed 002's two-way matching):
//   enhance (Gaussian + Wallis) -> points on the left: Förstner (a grid of local maxima) or,
//   in dense mode, every dense_step_px-th pixel -> approximate disparities from NCC on a
//   pyramid, for the left and for the right image, within a depth range -> at full
//   resolution NCC around the approximation -> the right image's own search must lead back
//   (two-way consistency) -> least-squares matching along the rows (on the Gaussian-only
//   images: see pair_matcher.cc; near points at half resolution, far ones with wide, low
//   windows) for the sub-pixel disparity and its sigma, which must agree with the way back too
//   -> the window must see one surface (the pyramid's disparities over it on its plane) and
//   fit it as well as its neighbours and the pair fit theirs (its grey residual against theirs).
// Coordinates are rectified pixels (rectification.h); depth = f B / disparity.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/matching/enhance.h"
#include "processing/matching/forstner.h"
#include "processing/matching/lsm.h"
#include "processing/matching/pyramid_ncc.h"
#include "processing/matching/rectification.h"

namespace ts {

// Least-squares matching of rectified pairs: along the rows, converged at 0.01 px, sigma at
// most 0.048 px (see PairMatchOptions::lsm); a window 2 half_width + 1 wide and 2 half_height + 1
// high (0: square).
inline LsmOptions StereoLsm(int half_width_px, int half_height_px = 0) {
  LsmOptions o;
  o.half_window_px = half_width_px;
  o.half_height_px = half_height_px;
  o.max_sigma_px = 0.048;
  o.convergence_px = 0.01;
  o.along_rows_only = true;
  return o;
}

struct PairMatchOptions {
  EnhanceOptions enhance;
  // Dense Förstner: the strongest pixel of every 4 x 4 cell that has texture at all;
  // least-squares matching decides which are good enough.
  ForstnerOptions interest = [] {
    ForstnerOptions o;
    o.cell_px = 4;
    o.local_maxima_only = false;
    o.min_roundness = 0.0;
    o.min_weight_factor = 0.01;
    o.subpixel = false;  // LSM windows are centred on pixels
    return o;
  }();
  int dense_step_px = 0;  // 0: Förstner points; n > 0: every n-th pixel of every n-th row
  // > 0: points closer together on the object than this (from the pyramid's depth) are
  // skipped, the first in image order kept. Near the tripod Förstner's image-space grid puts
  // hundreds of points on a square metre; a 1 m DEM needs a few dozen (`process` sets 0.1).
  double min_spacing_m = 0.0;
  PyramidNccOptions pyramid;
  int dense_finest_level = 1;  // pyramid maps down to this level; below it NCC per point
  int ncc_half_window_px = 3;  // full-resolution NCC around the approximation
  double min_ncc = 0.7;
  double min_depth_m = 1.5;  // nearest ground the rig can see
  double max_depth_m = 150.0;
  // An explicit disparity range instead of the depth range (both >= 0, max > min), e.g. for
  // a stereo pair without a known geometry; -1 = derive it from the depths.
  int min_disparity_px = -1;
  int max_disparity_px = -1;
  // 21 x 21 windows fitted along the rows only (the images are rectified, so a full affine
  // fit only adds parameters the geometry already fixes). A sigma above the limit marks most
  // blunders (windows across a crest). The error is noise-limited: larger windows help near
  // the tripod and hurt far out, where a window of ground spans metres of it in depth.
  LsmOptions lsm = StereoLsm(10);
  // Points nearer than this (by the pyramid's approximation) are least-squares matched on the
  // half-resolution images: there a pixel is a few millimetres of ground, the texture is smooth
  // at full resolution, and a window of the same size at half resolution sees four times the
  // ground with half the noise per pixel (their template centres move to even pixels). Much
  // farther, the window's ground curves over its depth. 0: never.
  double half_resolution_within_m = 7.0;
  // Their windows, in full-resolution pixels for the thresholds (halved at half resolution):
  // 17 x 17 pixels there still see 2.6 times the ground of a 21 x 21 window at full
  // resolution, for 35 % less work; the sigma limit grows with the fewer pixels (sqrt(441 /
  // 289)), so that the same precision of the ground passes.
  LsmOptions near_lsm = [] {
    LsmOptions n = StereoLsm(8);
    n.max_sigma_px = 0.059;
    return n;
  }();
  // Points farther than this are least-squares matched with far_lsm's wide, low windows: a
  // square window of far ground spans metres of it in depth (at 30 m each image row is ~40 cm
  // of ground seen from 1.5 m), where the ground is not the plane an affine fit assumes; the
  // rows a low window leaves out are those metres. Nearer, square windows are better. 0: never.
  double far_window_from_m = 20.0;
  LsmOptions far_lsm = StereoLsm(14, 4);
  // The right image's integer disparity may differ this much on the way back (the sigma
  // limit and the sub-pixel check catch what the slack lets through).
  int max_consistency_px = 2;
  // A window of which more than this share sees another surface (the pyramid's disparities
  // off its plane by more than max_consistency_px and the map's own pixel) is rejected: at an
  // occlusion edge least squares blends the two surfaces. 1: never.
  double max_other_surface_share = 0.1;
  // A match whose least-squares residual (the fit's sigma0, in grey levels) is more than this
  // many times the median residual of the matches around it (in the 3 x 3 squares of
  // residual_square_px round its square, at its resolution), or of all the pair's at its
  // resolution, whichever is smaller, is rejected. Image noise and the texture's own misfit are
  // alike in neighbouring windows; a window that holds what one plane cannot fit (ground
  // behind a lip blended with the lip, a small step in depth the pyramid's map cannot resolve)
  // leaves grey residuals several times theirs, and its disparity lies between the surfaces.
  // Where every window around is such a blend (a slope striped with lips), the pair's median
  // is the fit of one surface. 0: never.
  double max_residual_ratio = 3.0;
  int residual_square_px = 32;
  // The LSM sigma, from the fit's residuals, assumes independent pixels; smoothing and
  // resampling correlate neighbouring pixels, so the reported sigma is this times it
  // (calibrated against the simulator's true ranges in bench_matching).
  double sigma_scale = 3.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("dense_step_px", self.dense_step_px,
      {"every n-th pixel instead of Foerstner points (0: Foerstner)", "px", 0, 1000});
    v("min_spacing_m", self.min_spacing_m,
      {"points closer together on the object are skipped", "m", 0, 100});
    v("dense_finest_level", self.dense_finest_level,
      {"pyramid maps down to this level", "", 0, 10});
    v("ncc_half_window_px", self.ncc_half_window_px,
      {"full-resolution NCC half window", "px", 1, 50});
    v("min_ncc", self.min_ncc, {"weakest NCC accepted", "", -1, 1});
    v("min_depth_m", self.min_depth_m, {"nearest ground the rig can see", "m", 0.1, 10000});
    v("max_depth_m", self.max_depth_m, {"farthest ground matched", "m", 0.1, 100000});
    v("min_disparity_px", self.min_disparity_px,
      {"explicit disparity range (-1: from the depths)", "px", -1, 100000});
    v("max_disparity_px", self.max_disparity_px,
      {"explicit disparity range (-1: from the depths)", "px", -1, 100000});
    v("half_resolution_within_m", self.half_resolution_within_m,
      {"nearer points are matched at half resolution (0: never)", "m", 0, 1000});
    v("far_window_from_m", self.far_window_from_m,
      {"farther points get the wide, low windows (0: never)", "m", 0, 100000});
    v("max_consistency_px", self.max_consistency_px,
      {"the way back may differ this much", "px", 0, 100});
    v("max_other_surface_share", self.max_other_surface_share,
      {"reject a window of which more than this share sees another surface", "", 0, 1});
    v("max_residual_ratio", self.max_residual_ratio,
      {"reject a match whose residual is this many times its neighbours' or its pair's (0: never)",
       "", 0, 1000});
    v("residual_square_px", self.residual_square_px,
      {"the neighbours: the matches in the 3 x 3 squares this wide round a match", "px", 1, 10000});
    v("sigma_scale", self.sigma_scale,
      {"the LSM sigma times this (correlated pixels)", "", 0.01, 100});
    v.Group("enhance", self.enhance);
    v.Group("interest", self.interest);
    v.Group("pyramid", self.pyramid);
    v.Group("lsm", self.lsm);
    v.Group("near_lsm", self.near_lsm);
    v.Group("far_lsm", self.far_lsm);
  }
  bool Check(std::string* why) const;
  // For a station's DEM: points 20 cm apart on the ground (a 1 m DEM averages dozens a cell,
  // kriging thins to 25 cm) and 17 x 17 least-squares windows at sigma <= 0.075 px everywhere
  // (more, less precise points: the DEM's error is set by their number, not each one's
  // precision).
  static PairMatchOptions ForStation();
};

struct StereoMatch {
  Eigen::Vector2d left_px{0, 0};   // rectified left (the template centre)
  Eigen::Vector2d right_px{0, 0};  // rectified right (LSM)
  double disparity_px = 0.0;
  double sigma_disparity_px = 0.0;
  double correlation = 0.0;
  // Half the least-squares window's width and height, full-resolution pixels: matches whose
  // windows overlap share image noise, and so their errors.
  Eigen::Vector2d half_window_px{0, 0};
};

struct PairMatchSummary {
  int points = 0;
  int ncc_accepted = 0;
  int lsm_accepted = 0;
  int consistent = 0;
  int one_surface = 0;  // consistent, and the window sees one surface
  int fitting = 0;      // of those, the residual like its neighbours' and the pair's (returned)
  // wall time of the steps (s); the disparity maps and the interest points are found together
  double enhance_s = 0.0, maps_and_points_s = 0.0, matching_s = 0.0;
};

std::vector<StereoMatch> MatchRectifiedPair(const Rectification& rectification,
                                            const cv::Mat& left_rect, const cv::Mat& right_rect,
                                            const PairMatchOptions& options,
                                            PairMatchSummary* summary = nullptr);

}  // namespace ts
