#pragma once
// One camera's interior orientation from views of a planar target (a chessboard): a bundle
// adjustment (Ceres) of the project's one camera model (camera_model.h) and every view's
// pose, minimising the reprojection error in measured pixels, as OpenCV's calibrateCamera
// does, so that the two RMS compare. Starts from Zhang's closed form (OpenCV's
// initCameraMatrix2D) and each view's resection (solvePnP).
//
// The a posteriori figures: sigma0 (of one image coordinate, from the residuals and the
// redundancy), each parameter's sigma from the covariance of the adjustment (ceres::Covariance)
// scaled by sigma0^2, and the correlations above 0.9 named. Any parameter may be held fixed.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/geometry/camera_model.h"

namespace ts {

struct CameraCalibrationOptions {
  bool fix_k3 = false;
  bool fix_tangential = false;  // p1, p2
  bool fix_scale_x = false;     // the affinity (fx differs from fy)
  bool fix_shear = true;        // no sensor has shown one; frees a parameter few views fix
  double huber_px = 0.0;        // robust loss of a corner's residual; 0: least squares
  int max_iterations = 200;
  // A priori sigma of a detected corner. An adjustment whose sigma0 exceeds it many times
  // over does not describe the views (a wrong board size, corners matched to the wrong
  // points): refused, not written.
  double corner_sigma_px = 0.3;
  double max_sigma0_ratio = 10.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("fix_k3", self.fix_k3, {"hold k3 at zero"});
    v("fix_tangential", self.fix_tangential, {"hold p1 and p2 at zero"});
    v("fix_scale_x", self.fix_scale_x, {"hold the affinity at zero (square pixels)"});
    v("fix_shear", self.fix_shear, {"hold the shear at zero"});
    v("huber_px", self.huber_px, {"Huber loss scale (0: plain least squares)", "px", 0, 100});
    v("max_iterations", self.max_iterations, {"adjustment iterations, at most", "", 1, 10000});
    v("corner_sigma_px", self.corner_sigma_px, {"a priori sigma of a corner", "px", 1e-3, 10});
    v("max_sigma0_ratio", self.max_sigma0_ratio,
      {"sigma0 above this many a priori sigmas: the model does not fit", "", 1, 1000});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

// One planar target seen in several views; pixels[v][i] is target point i in view v.
struct PlanarViews {
  std::vector<Eigen::Vector3d> target;  // z = 0
  std::vector<std::string> names;       // one per view, for the report
  std::vector<std::vector<Eigen::Vector2d>> pixels;
};

struct CameraCalibration {
  CameraIntrinsics intrinsics;
  // A posteriori sigma of each parameter (kParameterNames order; 0 for a fixed one).
  std::array<double, CameraIntrinsics::kNumParameters> sigma{};
  Eigen::Matrix<double, CameraIntrinsics::kNumParameters, CameraIntrinsics::kNumParameters>
      correlation = decltype(correlation)::Zero();
  std::vector<std::string> high_correlations;  // "c / k1: 0.93"
  double rms_px = 0.0;     // sqrt(mean over corners of the squared 2D reprojection error)
  double sigma0_px = 0.0;  // of one image coordinate, a posteriori
  std::vector<double> view_rms_px;
  std::vector<Eigen::Isometry3d> camera_from_target;  // per view
  int observations = 0;                               // corners
  int iterations = 0;
  // The pinhole terms as OpenCV states them: fx, fy, cx, cy.
  double fx() const { return intrinsics.principal_distance_px / (1.0 + intrinsics.scale_x); }
  double fy() const { return intrinsics.principal_distance_px; }
  double cx() const { return intrinsics.principal_point_x_px; }
  double cy() const { return intrinsics.principal_point_y_px; }
};

// Needs at least three views (Zhang) of at least six points each.
Result<CameraCalibration> CalibrateCamera(const PlanarViews& views, int width_px, int height_px,
                                          const CameraCalibrationOptions& options);

}  // namespace ts
