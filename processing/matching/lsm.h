#pragma once
// Least-squares matching (Gruen 1985; seed 000 sec. 4.3.2, seed 001): a template window of
// the left image is matched into the right image under an affine geometric and a linear
// radiometric transformation,
//   f(x, y) + e(x, y) = r0 + r1 g(a0 + a1 x + a2 y,  b0 + b1 x + b2 y)
// with (x, y) relative to the template centre (or, for rectified stereo, along the rows only:
// b0 b1 b2 fixed at the template's row). The result is the sub-pixel position (a0, b0)
// in the search image with its standard deviation from the a-posteriori variance of the fit,
// and the correlation of the fitted windows.
//
// Solved in the inverse-compositional form (Baker & Matthews 2004): the Jacobian comes from
// the template's gradients, so the normal matrix is built once per point and each
// Gauss-Newton iteration only resamples the search window; the radiometric parameters are
// fitted in closed form at every iteration and projected out of the geometric Jacobian. It
// converges to the same minimum as the classic forward form, at a fraction of the cost.
// The Jacobian's columns are the template's gradients times (1, x, y), so it is never
// stored: the normal matrix comes from one pass of sums over the template window, and each
// iteration from one pass over the resampled window.
//
// Images are CV_32FC1; the template's gradients are passed in (compute them once per image
// with ComputeGradients()). The search window is resampled bilinearly: on smooth texture
// this biases the position by up to ~0.015 px near half-pixel shifts.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include "core/options.h"

namespace ts {

struct LsmOptions {
  int half_window_px = 7;  // template is (2h+1)^2 pixels
  int half_height_px = 0;  // > 0: the template is 2 half_window_px + 1 wide and 2 this + 1 high
  int max_iterations = 20;
  double convergence_px = 1e-3;  // stop when the shift update is smaller
  double max_shift_px = 3.0;     // reject if the match moves farther from the start
  double min_correlation = 0.7;  // reject weaker matches
  double max_sigma_px = 0.5;     // reject less precise matches
  // Rectified stereo: the match lies on the template's row (y = start's row, rounded), and
  // only x = a0 + a1 x + a2 y is fitted (Baltsavias' geometric constraint): three geometric
  // parameters instead of six, linear instead of bilinear resampling.
  bool along_rows_only = false;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("half_window_px", self.half_window_px, {"template half width", "px", 2, 50});
    v("half_height_px", self.half_height_px, {"template half height (0: square)", "px", 0, 50});
    v("max_iterations", self.max_iterations, {"iterations at most", "", 1, 1000});
    v("convergence_px", self.convergence_px,
      {"stop when the shift update is smaller", "px", 1e-9, 1});
    v("max_shift_px", self.max_shift_px,
      {"reject if the match moves farther from the start", "px", 0.01, 100});
    v("min_correlation", self.min_correlation, {"reject weaker matches", "", -1, 1});
    v("max_sigma_px", self.max_sigma_px, {"reject less precise matches", "px", 1e-6, 100});
    v("along_rows_only", self.along_rows_only,
      {"fit the shift along the rows only (rectified pairs)", "", 0, 1});
  }
  bool Check(std::string* why) const;
};

struct LsmResult {
  bool ok = false;
  std::string why;                    // reason for rejection when !ok
  Eigen::Vector2d position_px{0, 0};  // matched point in the search image
  double sigma_x_px = 0.0, sigma_y_px = 0.0;
  double sigma0 = 0.0;  // a-posteriori grey-value residual (template grey levels)
  double correlation = 0.0;
  int iterations = 0;
  // a0 a1 a2 b0 b1 b2 r0 r1
  Eigen::Matrix<double, 8, 1> parameters = Eigen::Matrix<double, 8, 1>::Zero();
};

struct ImageGradients {
  cv::Mat dx, dy;  // CV_32FC1, central differences (0 on the border)
};
ImageGradients ComputeGradients(const cv::Mat& image);

// centre: the template window's centre pixel in `templ`, whose gradients are given;
// start: approximate position in `search` (within ~1-2 px of the truth); start_shape: the
// warp's linear part to start from (a1 a2; b1 b2), e.g. a neighbour's fit: on a slanted
// surface it saves the iterations that would find the shear (identity when null).
LsmResult MatchLsm(const cv::Mat& templ, const ImageGradients& template_gradients,
                   const cv::Point& centre, const cv::Mat& search, const Eigen::Vector2d& start,
                   const LsmOptions& options = {}, const Eigen::Matrix2d* start_shape = nullptr);

}  // namespace ts
