#pragma once
// One camera's interior orientation, and the stereo pair's, from views of a target (a
// chessboard, a ChArUco board, a control field): the adjustment of target_adjustment.h with
// what a calibration user asks of it. Each parameter's sigma from the covariance scaled by
// sigma0^2, the correlations above 0.9 named, the share of observations rejected (a warning
// above 3 %), the distortion terms the data do not support fixed at zero (unless kept), and a
// refusal when sigma0 exceeds the corners' a priori sigma many times over (a wrong board size,
// corners matched to the wrong points): such an adjustment is not written.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/calibration/target_adjustment.h"
#include "processing/calibration/target_views.h"
#include "processing/geometry/calibration.h"
#include "processing/geometry/camera_model.h"
#include "processing/geometry/stereo_rig.h"

namespace ts {

struct CameraCalibrationOptions {
  bool fix_principal_point = false;
  bool fix_k3 = false;
  bool fix_tangential = false;  // p1, p2
  bool fix_scale_x = false;     // the affinity (fx differs from fy)
  bool fix_shear = false;
  // A distortion or affinity term below this |estimate| / sigma is fixed at zero and the
  // adjustment repeated, least significant first (about 95 % two-sided).
  double significance_t = 2.0;
  bool keep_all_terms = false;  // no significance test: every free term stays free
  // A priori sigma of a detected corner. An adjustment whose sigma0 exceeds it many times
  // over does not describe the views: refused, not written.
  double corner_sigma_px = 0.3;
  double max_sigma0_ratio = 10.0;
  double warn_rejected_share = 0.03;
  double warn_border_coverage = 0.75;
  TargetAdjustmentOptions adjustment;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("fix_principal_point", self.fix_principal_point, {"hold the principal point"});
    v("fix_k3", self.fix_k3, {"hold k3 at zero"});
    v("fix_tangential", self.fix_tangential, {"hold p1 and p2 at zero"});
    v("fix_scale_x", self.fix_scale_x, {"hold the affinity at zero (square pixels)"});
    v("fix_shear", self.fix_shear, {"hold the shear at zero"});
    v("significance_t", self.significance_t,
      {"fix distortion terms whose |estimate|/sigma is below this", "", 0, 100});
    v("keep_all_terms", self.keep_all_terms, {"keep every free term, significant or not"});
    v("corner_sigma_px", self.corner_sigma_px, {"a priori sigma of a corner", "px", 1e-3, 10});
    v("max_sigma0_ratio", self.max_sigma0_ratio,
      {"sigma0 above this many a priori sigmas: the model does not fit", "", 1, 1000});
    v("warn_rejected_share", self.warn_rejected_share,
      {"warn when more observations than this share are rejected", "", 0, 1});
    v("warn_border_coverage", self.warn_border_coverage,
      {"warn when fewer of the cells along the frame's edges hold an observation", "", 0, 1});
    v.Group("adjustment", self.adjustment);
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

// One measured point after the adjustment, for the report's pictures.
struct ObservedResidual {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Vector2d residual = Eigen::Vector2d::Zero();  // measured minus projected
  int view = 0;                                        // index into view_names
  bool rejected = false;
};

struct CameraCalibration {
  CameraIntrinsics intrinsics;
  // A posteriori sigma of each parameter (kParameterNames order; 0 for a fixed one).
  std::array<double, kIntrinsicCount> sigma{};
  IntrinsicMatrix covariance = IntrinsicMatrix::Zero();
  IntrinsicMatrix correlation = IntrinsicMatrix::Zero();
  std::vector<std::string> high_correlations;    // "c / k1: 0.93"
  std::vector<std::string> fixed_insignificant;  // "k3 (t 0.4)"
  double rms_px = 0.0;     // sqrt(mean over all measured points of the squared 2D error)
  double sigma0_px = 0.0;  // of one image coordinate, a posteriori, from the inliers
  std::vector<std::string> view_names;
  std::vector<double> view_rms_px;
  std::vector<ObservedResidual> residuals;
  std::vector<Eigen::Isometry3d> camera_from_target;  // per view
  // The target points as adjusted: a control field's surveyed points moved within their
  // sigma; a board's as given.
  std::vector<Eigen::Vector3d> target;
  int observations = 0;  // measured points
  int rejected = 0;
  FrameCoverage coverage;
  int iterations = 0;
  std::vector<std::string> warnings;
  // The pinhole terms as OpenCV states them: fx, fy, cx, cy.
  double fx() const { return intrinsics.principal_distance_px / (1.0 + intrinsics.scale_x); }
  double fy() const { return intrinsics.principal_distance_px; }
  double cx() const { return intrinsics.principal_point_x_px; }
  double cy() const { return intrinsics.principal_point_y_px; }
};

// Needs at least three views (Zhang) of at least six points each, or a starting camera for a
// 3D target.
Result<CameraCalibration> CalibrateCamera(const TargetViews& views,
                                          const CameraCalibrationOptions& options,
                                          const CameraIntrinsics* start = nullptr);

// Both cameras and the relative orientation in one adjustment, over the placements of the
// target (placement ids pair the views; a view seen by one camera only still counts).
struct StereoCalibration {
  CameraCalibration left, right;
  Eigen::Isometry3d right_from_left = Eigen::Isometry3d::Identity();  // OpenCV's R, T
  double baseline = 0.0;                                              // in the target's unit
  double baseline_sigma = 0.0;
  Eigen::Vector3d angles_deg = Eigen::Vector3d::Zero();  // omega phi kappa of left_from_right
  Eigen::Vector3d angles_sigma_deg = Eigen::Vector3d::Zero();
  // Of (baseline, omega, phi, kappa), in the target's unit and degrees.
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  // Of every parameter jointly: the left intrinsics, the right's, right_from_left as a Pose6.
  Eigen::MatrixXd joint_covariance;
  // The same with (baseline, omega, phi, kappa) for the Pose6: StereoPrecision::joint_covariance.
  Eigen::MatrixXd rig_joint_covariance;
  double rms_px = 0.0;  // over the measured points of both images
  double sigma0_px = 0.0;
  int observations = 0;
  int rejected = 0;
  std::vector<std::string> warnings;
  // The rig, its baseline scaled to metres by metres_per_unit (the target's unit in m).
  StereoRig Rig(double metres_per_unit) const;
};

Result<StereoCalibration> CalibrateStereo(const TargetViews& left, const TargetViews& right,
                                          const CameraCalibrationOptions& options,
                                          const CameraIntrinsics* left_start = nullptr,
                                          const CameraIntrinsics* right_start = nullptr);

// A camera's adjusted precision as calibration.yaml keeps it.
CameraPrecision PrecisionOf(const CameraCalibration& c);

// The stereo result as a calibration `process` reads: the stage kinematics and the rig's roll
// about its baseline from `previous` (the stage is calibrated on the rig, not on a board), or
// the ideal stage and the roll that levels the mean viewing axis.
Calibration CalibrationOf(const StereoCalibration& s, const std::optional<Calibration>& previous);

}  // namespace ts
