#include "processing/geometry/stage_kinematics.h"

#include <cmath>

#include "processing/geometry/rotation.h"

namespace ts {
namespace {
Eigen::Isometry3d Rigid(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = rotation;
  t.translation() = translation;
  return t;
}
// A stage whose "small" calibration angles exceed this is misassembled, not miscalibrated.
constexpr double kMaxSmallAngleDeg = 10.0;
constexpr double kMaxOffsetM = 1.0;
}  // namespace

bool StageKinematics::Check(std::string* why) const {
  std::string err;
  const double angles[] = {levelling_x_deg,          levelling_y_deg,
                           tilt_axis_skew_deg,       rig_rotation_opk_deg.x(),
                           rig_rotation_opk_deg.y(), rig_rotation_opk_deg.z()};
  for (double a : angles) {
    if (!std::isfinite(a) || std::abs(a) > kMaxSmallAngleDeg)
      err = "levelling, skew and rig rotation must be finite and within 10 deg";
  }
  if (!std::isfinite(pan_zero_deg) || !std::isfinite(tilt_zero_deg))
    err = "encoder zero offsets must be finite";
  if (!tilt_axis_offset_m.allFinite() || tilt_axis_offset_m.norm() > kMaxOffsetM ||
      !rig_offset_m.allFinite() || rig_offset_m.norm() > kMaxOffsetM)
    err = "mount offsets must be finite and within 1 m";
  if (!std::isfinite(height_above_mark_m) || height_above_mark_m < 0.0)
    err = "height_above_mark_m must be finite and not negative";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

Eigen::Isometry3d StageKinematics::LFromS(double pan_deg, double tilt_deg) const {
  const Eigen::Isometry3d levelling =
      Rigid(RotationX(RadFromDeg(levelling_x_deg)) * RotationY(RadFromDeg(levelling_y_deg)),
            Eigen::Vector3d::Zero());
  // Clockwise from above = negative rotation about +Z.
  const Eigen::Isometry3d pan =
      Rigid(RotationZ(-RadFromDeg(pan_deg - pan_zero_deg)), Eigen::Vector3d::Zero());
  const Eigen::Isometry3d mount =
      Rigid(RotationY(RadFromDeg(tilt_axis_skew_deg)), tilt_axis_offset_m);
  // Positive tilt raises +Y towards +Z: positive rotation about +X.
  const Eigen::Isometry3d tilt =
      Rigid(RotationX(RadFromDeg(tilt_deg - tilt_zero_deg)), Eigen::Vector3d::Zero());
  const Opk rig_opk{RadFromDeg(rig_rotation_opk_deg.x()), RadFromDeg(rig_rotation_opk_deg.y()),
                    RadFromDeg(rig_rotation_opk_deg.z())};
  const Eigen::Isometry3d rig = Rigid(RotationFromOpk(rig_opk), rig_offset_m);
  return levelling * pan * mount * tilt * rig;
}

}  // namespace ts
