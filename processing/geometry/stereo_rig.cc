#include "processing/geometry/stereo_rig.h"

#include <cmath>
#include <sstream>
#include <string>

namespace ts {
namespace {
bool IsRotation(const Eigen::Matrix3d& r) {
  return r.allFinite() && (r * r.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-9 &&
         std::abs(r.determinant() - 1.0) < 1e-9;
}
}  // namespace

// A stereo rig on a stage: a centimetre to a few metres between the cameras.
constexpr double kMinBaselineM = 0.01, kMaxBaselineM = 10.0;

bool StereoRig::Check(std::string* why) const {
  std::string err;
  if (!left.Check(&err))
    err = "left camera: " + err;
  else if (!right.Check(&err))
    err = "right camera: " + err;
  else if (!std::isfinite(baseline_m) || baseline_m < kMinBaselineM || baseline_m > kMaxBaselineM)
    err = (std::ostringstream() << "baseline_m must be " << kMinBaselineM << " to " << kMaxBaselineM
                                << " m, got " << baseline_m)
              .str();
  else if (!IsRotation(S_from_left))
    err = "S_from_left is not a rotation";
  else if (!IsRotation(left_from_right))
    err = "left_from_right is not a rotation";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

Eigen::Matrix3d StereoRig::NominalSFromCamera() {
  Eigen::Matrix3d r;
  // columns: camera x -> +X_S, camera y -> -Z_S, camera z -> +Y_S
  r << 1, 0, 0,  //
      0, 0, 1,   //
      0, -1, 0;
  return r;
}

Eigen::Isometry3d StereoRig::SFromLeftCamera() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = S_from_left;
  t.translation() = Eigen::Vector3d(-0.5 * baseline_m, 0.0, 0.0);
  return t;
}

Eigen::Isometry3d StereoRig::SFromRightCamera() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = S_from_left * left_from_right;
  t.translation() = Eigen::Vector3d(0.5 * baseline_m, 0.0, 0.0);
  return t;
}

Eigen::Isometry3d StereoRig::RightFromLeftCamera() const {
  return SFromRightCamera().inverse() * SFromLeftCamera();
}

StereoRig StereoRig::FromStereoCalibration(const CameraIntrinsics& left,
                                           const CameraIntrinsics& right,
                                           const Eigen::Matrix3d& right_from_left_rotation,
                                           const Eigen::Vector3d& right_from_left_translation_m) {
  // Right projection centre in the left camera frame: 0 = R c + t  =>  c = -R^T t.
  const Eigen::Vector3d baseline_in_left =
      -right_from_left_rotation.transpose() * right_from_left_translation_m;
  const Eigen::Vector3d x_axis = baseline_in_left.normalized();
  // Mean viewing direction of both cameras, in the left frame.
  const Eigen::Vector3d mean_view =
      Eigen::Vector3d::UnitZ() + right_from_left_rotation.transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d y_axis = (mean_view - mean_view.dot(x_axis) * x_axis).normalized();
  const Eigen::Vector3d z_axis = x_axis.cross(y_axis);

  StereoRig rig;
  rig.left = left;
  rig.right = right;
  rig.baseline_m = baseline_in_left.norm();
  // Rows of S_from_left are the S axes expressed in the left camera frame.
  rig.S_from_left.row(0) = x_axis.transpose();
  rig.S_from_left.row(1) = y_axis.transpose();
  rig.S_from_left.row(2) = z_axis.transpose();
  rig.left_from_right = right_from_left_rotation.transpose();
  return rig;
}

}  // namespace ts
