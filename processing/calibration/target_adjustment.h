#pragma once
// The bundle adjustment behind every calibration (Ceres): one or two cameras of the project's
// one camera model (camera_model.h) and the target's pose at each placement, minimising the
// reprojection error in measured pixels, as OpenCV's calibrateCamera and stereoCalibrate do,
// so that the RMS compare. With two cameras the second is tied to the first by one relative
// orientation (seed 003 eq. 2) over every placement both saw: a joint adjustment, not two
// calibrations glued together.
//
// A control field's points are surveyed, not exact: each is adjusted with its surveyed
// coordinates as observations of their sigma, weighed against the images by the images' sigma
// estimated as a variance component (Foerstner), so that the survey's errors reach the sigmas
// of the cameras instead of bending them unseen.
//
// After the solve: observations off by more than k sigma0 are rejected and the adjustment is
// repeated; sigma0 a posteriori from the inliers' residuals and the redundancy; the
// covariance of the intrinsics and of the relative orientation (ceres::Covariance) scaled by
// sigma0^2. A distortion term whose estimate is not significantly different from zero can be
// fixed at zero and the adjustment repeated (FixInsignificantTerms).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/calibration/target_views.h"
#include "processing/geometry/camera_model.h"

namespace ts {

struct TargetAdjustmentOptions {
  double huber_px = 0.0;  // robust loss of a point's residual; 0: least squares
  int max_iterations = 200;
  // An observation whose residual exceeds k sigma0 in x or y is rejected; rounds repeat the
  // adjustment until the judgement stands. k = 0: k from the number of observations, so that
  // normal errors exceed it anywhere in the set with probability rejection_alpha (real corner
  // errors have heavier tails than that; a fixed k of 3 or 4 cuts into them round after round).
  double rejection_k = 0.0;
  double rejection_alpha = 0.001;
  int max_rejection_rounds = 5;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("huber_px", self.huber_px, {"Huber loss scale (0: plain least squares)", "px", 0, 100});
    v("max_iterations", self.max_iterations, {"adjustment iterations, at most", "", 1, 10000});
    v("rejection_k", self.rejection_k,
      {"reject observations off by more than k sigma0 (0: k from rejection_alpha)", "", 0, 100});
    v("rejection_alpha", self.rejection_alpha,
      {"chance that a normal error anywhere in the set is rejected (k 0)", "", 1e-12, 0.5});
    v("max_rejection_rounds", self.max_rejection_rounds,
      {"adjustments repeated after rejections, at most", "", 0, 100});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

constexpr int kIntrinsicCount = CameraIntrinsics::kNumParameters;
using IntrinsicVector = std::array<double, kIntrinsicCount>;
using IntrinsicMatrix = Eigen::Matrix<double, kIntrinsicCount, kIntrinsicCount>;
using Pose6 = std::array<double, 6>;  // angle-axis, translation: to = R from + t

// The unknowns and what they are adjusted to.
struct TargetAdjustment {
  std::vector<TargetViews> cameras;  // one or two, sharing one target
  // The target points as adjusted: the surveyed ones (TargetViews::target_sigma) move within
  // their sigma, weighed against image observations of sigma image_sigma_px (0: every point
  // held as given).
  std::vector<Eigen::Vector3d> target;
  double image_sigma_px = 0.0;
  std::vector<IntrinsicVector> intrinsics;
  std::vector<std::array<bool, kIntrinsicCount>> fixed;
  std::map<int, Pose6> first_from_target;                // per placement, in the first camera
  Pose6 second_from_first{};                             // two cameras only
  std::vector<std::vector<std::vector<char>>> rejected;  // [camera][view][pixel]
  // [camera] the names of the views left out because no pose was found from their points.
  std::vector<std::vector<std::string>> unresected;

  Eigen::Isometry3d CameraFromTarget(int camera, int placement) const;
  Eigen::Isometry3d SecondFromFirst() const;
  CameraIntrinsics Intrinsics(int camera) const;
  int FreeParameters() const;
};

struct AdjustmentPrecision {
  double sigma0_px = 0.0;  // of one image coordinate, from the inliers
  int observations = 0;    // measured points, every camera
  int rejected = 0;
  double rejection_k = 0.0;  // the k applied
  int redundancy = 0;
  int iterations = 0;
  // False when the normal matrix is singular (some free parameter not determined); the
  // covariances are then unknown.
  bool determined = true;
  // Of the calibration's parameters, jointly: each camera's intrinsics (kIntrinsicCount each),
  // then the relative orientation (Pose6, two cameras only); 0 rows for fixed terms.
  Eigen::MatrixXd covariance;
  IntrinsicMatrix IntrinsicsCovariance(int camera) const {
    return covariance.block<kIntrinsicCount, kIntrinsicCount>(kIntrinsicCount * camera,
                                                              kIntrinsicCount * camera);
  }
};

// The starting point: for a camera without a given one, Zhang's closed form (OpenCV's
// initCameraMatrix2D; planar targets only), then each view's resection (solvePnP), and the
// relative orientation from the placements both cameras saw.
Status InitialiseTargetAdjustment(TargetAdjustment* adjustment,
                                  const std::vector<const CameraIntrinsics*>& given);

// Solves, rejects, solves again; then the precision. Errors when the adjustment fails.
Result<AdjustmentPrecision> SolveTargetAdjustment(TargetAdjustment* adjustment,
                                                  const TargetAdjustmentOptions& options);

Eigen::Isometry3d IsometryFromPose(const Pose6& pose);
// A camera's pose from target points and their measured pixels (four or more), the distortion
// undone first: SQPnP, then Levenberg-Marquardt on the reprojection error (OpenCV).
std::optional<Eigen::Isometry3d> Resect(const std::vector<Eigen::Vector3d>& target,
                                        const std::vector<Eigen::Vector2d>& pixels,
                                        const CameraIntrinsics& camera);
Pose6 PoseFromIsometry(const Eigen::Isometry3d& isometry);

// The measured minus the projected pixel, [camera][view][pixel] (the project's projection).
std::vector<std::vector<std::vector<Eigen::Vector2d>>> TargetResiduals(
    const TargetAdjustment& adjustment);

// Backward elimination of distortion terms (k1 k2 k3 p1 p2 scale_x shear): while the least
// significant free term, |estimate| / sigma, is below t_critical and not kept, it is fixed at
// zero and the adjustment solved again. Returns, per camera, "k3 (t 0.4)" for each term fixed.
// The covariances left in precision are the full model's (its sigmas cover what fixing a term
// at zero may have shifted); sigma0 and the rejections are the reduced model's.
Result<std::vector<std::vector<std::string>>> FixInsignificantTerms(
    TargetAdjustment* adjustment, const TargetAdjustmentOptions& options, double t_critical,
    AdjustmentPrecision* precision);

}  // namespace ts
