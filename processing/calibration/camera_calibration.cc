#include "processing/calibration/camera_calibration.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "processing/geometry/rotation.h"

namespace ts {
namespace {

constexpr int kN = kIntrinsicCount;

std::array<bool, kN> HeldTerms(const CameraCalibrationOptions& o) {
  std::array<bool, kN> held{};
  held[1] = held[2] = o.fix_principal_point;
  held[5] = o.fix_k3;
  held[6] = held[7] = o.fix_tangential;
  held[8] = o.fix_scale_x;
  held[9] = o.fix_shear;
  return held;
}

// The adjustment from its starting point, the insignificant terms fixed, then the fit judged.
Result<AdjustmentPrecision> Adjust(TargetAdjustment* a, const CameraCalibrationOptions& o,
                                   std::vector<std::vector<std::string>>* fixed_insignificant) {
  for (auto& held : a->fixed) held = HeldTerms(o);
  for (size_t c = 0; c < a->intrinsics.size(); ++c)
    for (int j = 0; j < kN; ++j)
      if (a->fixed[c][j] && j >= 3) a->intrinsics[c][j] = 0.0;
  Result<AdjustmentPrecision> precision = SolveTargetAdjustment(a, o.adjustment);
  if (precision && !o.keep_all_terms) {
    auto fixed = FixInsignificantTerms(a, o.adjustment, o.significance_t, &*precision);
    if (!fixed) return Error{fixed.error()};
    *fixed_insignificant = *fixed;
  }
  if (!precision) return precision;
  if (precision->sigma0_px > o.max_sigma0_ratio * o.corner_sigma_px)
    return Error{"the adjustment does not fit the views (sigma0 " +
                 fmt::format("{:.3f}", precision->sigma0_px) + " px against corners good to " +
                 fmt::format("{:.2f}", o.corner_sigma_px) + " px): is the board size right?"};
  if (!precision->determined)
    return Error{
        "the views do not determine every free parameter (the normal matrix is singular): add "
        "views at other angles, or fix k3, p1 p2"};
  return precision;
}

CameraCalibration DescribeCamera(const TargetAdjustment& a, const AdjustmentPrecision& precision,
                                 const std::vector<std::vector<Eigen::Vector2d>>& residuals, int c,
                                 const CameraCalibrationOptions& o) {
  CameraCalibration r;
  r.intrinsics = a.Intrinsics(c);
  r.covariance = precision.IntrinsicsCovariance(c);
  for (int i = 0; i < kN; ++i) r.sigma[i] = std::sqrt(std::max(0.0, r.covariance(i, i)));
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) {
      const double s = r.sigma[i] * r.sigma[j];
      r.correlation(i, j) = s > 0.0 ? r.covariance(i, j) / s : (i == j ? 1.0 : 0.0);
      if (j > i && std::abs(r.correlation(i, j)) > 0.9)
        r.high_correlations.push_back(std::string(CameraIntrinsics::kParameterNames[i]) + " / " +
                                      CameraIntrinsics::kParameterNames[j] + ": " +
                                      fmt::format("{:.2f}", r.correlation(i, j)));
    }
  const TargetViews& views = a.cameras[c];
  double total = 0.0;
  for (size_t v = 0; v < views.views.size(); ++v) {
    double view = 0.0;
    for (size_t i = 0; i < residuals[v].size(); ++i) {
      view += residuals[v][i].squaredNorm();
      r.rejected += a.rejected[c][v][i];
      r.residuals.push_back({views.views[v].pixels[i], residuals[v][i], static_cast<int>(v),
                             a.rejected[c][v][i] != 0});
    }
    total += view;
    r.observations += static_cast<int>(residuals[v].size());
    r.view_names.push_back(views.views[v].name);
    r.view_rms_px.push_back(std::sqrt(view / std::max<size_t>(1, residuals[v].size())));
    r.camera_from_target.push_back(a.CameraFromTarget(c, views.views[v].placement));
  }
  r.rms_px = std::sqrt(total / std::max(1, r.observations));
  r.target = a.target;
  r.sigma0_px = precision.sigma0_px;
  r.iterations = precision.iterations;
  r.coverage = views.Coverage();
  if (r.coverage.border_share < o.warn_border_coverage)
    r.warnings.push_back(
        "observations in only " + fmt::format("{:.0f}", 100.0 * r.coverage.border_share) +
        " % of the cells along the frame's edges: the distortion there is extrapolated; add "
        "views with the board at the edges and corners of the frame");
  for (const std::string& name : a.unresected[c])
    r.warnings.push_back("view " + name +
                         " left out: no pose fits its points (all on one line or one spot)");
  const double share = static_cast<double>(r.rejected) / std::max(1, r.observations);
  if (share > o.warn_rejected_share)
    r.warnings.push_back(fmt::format("{:.1f}", 100.0 * share) +
                         " % of the observations rejected (" + std::to_string(r.rejected) + " of " +
                         std::to_string(r.observations) +
                         "): blurred views or corners found at wrong places");
  return r;
}

// (baseline, omega, phi, kappa of left_from_right) from right_from_left as Ceres holds it.
Eigen::Vector4d RelativeOrientation(const Pose6& right_from_left) {
  const Eigen::Isometry3d left_from_right = IsometryFromPose(right_from_left).inverse();
  const Eigen::Vector3d opk_deg = OpkDegFromRotation(left_from_right.linear());
  return {left_from_right.translation().norm(), opk_deg.x(), opk_deg.y(), opk_deg.z()};
}

// Its derivative by the pose (central differences), for first-order propagation of the
// adjustment's covariance.
Eigen::Matrix<double, 4, 6> RelativeOrientationJacobian(const Pose6& pose) {
  Eigen::Matrix<double, 4, 6> jacobian;
  for (int j = 0; j < 6; ++j) {
    const double h = j < 3 ? 1e-7 : 1e-7 * std::max(1.0, std::abs(pose[j]));
    Pose6 plus = pose, minus = pose;
    plus[j] += h, minus[j] -= h;
    jacobian.col(j) = (RelativeOrientation(plus) - RelativeOrientation(minus)) / (2.0 * h);
  }
  return jacobian;
}

// The adjustment's joint covariance (both cameras' intrinsics, then the Pose6) with the pose's
// columns carried into (baseline, omega, phi, kappa).
Eigen::MatrixXd RigJointCovariance(const Pose6& pose, const Eigen::MatrixXd& joint) {
  constexpr int kCameras = 2 * kIntrinsicCount;
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(kCameras + 4, kCameras + 6);
  jacobian.topLeftCorner(kCameras, kCameras).setIdentity();
  jacobian.bottomRightCorner(4, 6) = RelativeOrientationJacobian(pose);
  return jacobian * joint * jacobian.transpose();
}

}  // namespace

Result<CameraCalibration> CalibrateCamera(const TargetViews& views,
                                          const CameraCalibrationOptions& o,
                                          const CameraIntrinsics* start) {
  std::string why;
  if (!o.Check(&why)) return Error{"camera calibration: " + why};
  TargetAdjustment a;
  a.cameras = {views};
  if (Status s = InitialiseTargetAdjustment(&a, {start}); !s)
    return Error{"camera calibration: " + s.error()};
  std::vector<std::vector<std::string>> insignificant(1);
  const Result<AdjustmentPrecision> precision = Adjust(&a, o, &insignificant);
  if (!precision) return Error{"camera calibration: " + precision.error()};
  CameraCalibration r = DescribeCamera(a, *precision, TargetResiduals(a)[0], 0, o);
  r.fixed_insignificant = insignificant[0];
  return r;
}

StereoRig StereoCalibration::Rig(double metres_per_unit) const {
  return StereoRig::FromStereoCalibration(left.intrinsics, right.intrinsics,
                                          right_from_left.linear(),
                                          metres_per_unit * right_from_left.translation());
}

Result<StereoCalibration> CalibrateStereo(const TargetViews& left, const TargetViews& right,
                                          const CameraCalibrationOptions& o,
                                          const CameraIntrinsics* left_start,
                                          const CameraIntrinsics* right_start) {
  std::string why;
  if (!o.Check(&why)) return Error{"stereo calibration: " + why};
  TargetAdjustment a;
  a.cameras = {left, right};
  if (Status s = InitialiseTargetAdjustment(&a, {left_start, right_start}); !s)
    return Error{"stereo calibration: " + s.error()};
  StereoCalibration r;
  std::vector<std::vector<std::string>> insignificant(2);
  const Result<AdjustmentPrecision> precision = Adjust(&a, o, &insignificant);
  if (!precision) return Error{"stereo calibration: " + precision.error()};
  const auto residuals = TargetResiduals(a);
  r.left = DescribeCamera(a, *precision, residuals[0], 0, o);
  r.right = DescribeCamera(a, *precision, residuals[1], 1, o);
  r.left.fixed_insignificant = insignificant[0];
  r.right.fixed_insignificant = insignificant[1];
  const Pose6& pose = a.second_from_first;
  r.right_from_left = a.SecondFromFirst();
  const Eigen::Vector4d relative = RelativeOrientation(pose);
  r.joint_covariance = precision->covariance;
  r.rig_joint_covariance = RigJointCovariance(pose, r.joint_covariance);
  r.covariance = r.rig_joint_covariance.bottomRightCorner<4, 4>();
  r.baseline = relative[0];
  r.baseline_sigma = std::sqrt(r.covariance(0, 0));
  r.angles_deg = relative.tail<3>();
  for (int j = 0; j < 3; ++j) r.angles_sigma_deg[j] = std::sqrt(r.covariance(1 + j, 1 + j));
  r.observations = r.left.observations + r.right.observations;
  r.rejected = r.left.rejected + r.right.rejected;
  r.rms_px = std::sqrt((r.left.rms_px * r.left.rms_px * r.left.observations +
                        r.right.rms_px * r.right.rms_px * r.right.observations) /
                       std::max(1, r.observations));
  r.sigma0_px = precision->sigma0_px;
  for (const CameraCalibration* camera : {&r.left, &r.right})
    for (const std::string& w : camera->warnings)
      r.warnings.push_back((camera == &r.left ? "left: " : "right: ") + w);
  return r;
}

CameraPrecision PrecisionOf(const CameraCalibration& c) {
  return {true, c.sigma, c.covariance, c.rms_px};
}

Calibration CalibrationOf(const StereoCalibration& s, const std::optional<Calibration>& previous) {
  Calibration cal;
  cal.rig = s.Rig(1.0);
  if (previous) {
    cal.stage = previous->stage;
    // X_S stays the calibrated baseline; Y_S as near the previous rig's as that allows.
    const Eigen::Vector3d x = cal.rig.S_from_left.row(0).transpose();
    const Eigen::Vector3d previous_y = previous->rig.S_from_left.row(1).transpose();
    const Eigen::Vector3d y = (previous_y - previous_y.dot(x) * x).normalized();
    cal.rig.S_from_left.row(1) = y.transpose();
    cal.rig.S_from_left.row(2) = x.cross(y).transpose();
  }
  cal.left_precision = PrecisionOf(s.left);
  cal.right_precision = PrecisionOf(s.right);
  cal.stereo_precision = {true,         s.baseline_sigma, s.angles_sigma_deg,
                          s.covariance, s.rms_px,         s.rig_joint_covariance};
  return cal;
}

}  // namespace ts
