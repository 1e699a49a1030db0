#include "processing/geometry/stage_kinematics.h"

#include <cmath>

#include "core/options.h"

#include "processing/geometry/rotation.h"

namespace ts {
namespace {
// A stage whose "small" calibration angles exceed this is misassembled, not miscalibrated.
constexpr double kMaxSmallAngleDeg = 10.0;
constexpr double kMaxOffsetM = 1.0;
constexpr double kMaxHeightAboveMarkM = 10.0;
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
  if (!(std::abs(pan_zero_deg) <= 360.0) || !(std::abs(tilt_zero_deg) <= 360.0))
    err = "encoder zero offsets must be within 360 deg";
  if (!tilt_axis_offset_m.allFinite() || tilt_axis_offset_m.norm() > kMaxOffsetM ||
      !rig_offset_m.allFinite() || rig_offset_m.norm() > kMaxOffsetM)
    err = "mount offsets must be finite and within 1 m";
  if (!std::isfinite(height_above_mark_m) || height_above_mark_m < 0.0 ||
      height_above_mark_m > kMaxHeightAboveMarkM)
    err = "height_above_mark_m must be 0 to 10 m (a tripod or a mast)";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

Status StageKinematics::SetInstrumentHeight(double instrument_height_m) {
  if (!(instrument_height_m >= tilt_axis_offset_m.z()))
    return Error{"instrument height " + OptionNumberText(instrument_height_m) +
                 " m: below the stage's own height of its tilt axis over its origin (" +
                 OptionNumberText(tilt_axis_offset_m.z()) + " m)"};
  height_above_mark_m = instrument_height_m - tilt_axis_offset_m.z();
  return {};
}

Eigen::Isometry3d StageKinematics::LFromS(double pan_deg, double tilt_deg) const {
  const StageVector v = StageVectorOf(*this);
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  LFromSOf(v.data(), pan_deg, tilt_deg, &rotation, &translation);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = rotation;
  t.translation() = translation;
  return t;
}

const char* const kStageParameterNames[kStageParameterCount] = {
    "levelling_x_deg",      "levelling_y_deg",      "pan_zero_deg",         "tilt_zero_deg",
    "tilt_axis_offset_x_m", "tilt_axis_offset_y_m", "tilt_axis_offset_z_m", "tilt_axis_skew_deg",
    "rig_offset_x_m",       "rig_offset_y_m",       "rig_offset_z_m",       "rig_omega_deg",
    "rig_phi_deg",          "rig_kappa_deg"};

StageVector StageVectorOf(const StageKinematics& s) {
  return {s.levelling_x_deg,
          s.levelling_y_deg,
          s.pan_zero_deg,
          s.tilt_zero_deg,
          s.tilt_axis_offset_m.x(),
          s.tilt_axis_offset_m.y(),
          s.tilt_axis_offset_m.z(),
          s.tilt_axis_skew_deg,
          s.rig_offset_m.x(),
          s.rig_offset_m.y(),
          s.rig_offset_m.z(),
          s.rig_rotation_opk_deg.x(),
          s.rig_rotation_opk_deg.y(),
          s.rig_rotation_opk_deg.z()};
}

double SightTiltSigmaDeg(const StageVector& sigma) {
  const double levelling2 = 0.5 * (sigma[0] * sigma[0] + sigma[1] * sigma[1]);
  return std::sqrt(levelling2 + sigma[3] * sigma[3] + sigma[11] * sigma[11]);
}

StageKinematics StageKinematicsOf(const StageVector& v, const StageKinematics& stage) {
  StageKinematics s = stage;
  s.levelling_x_deg = v[0];
  s.levelling_y_deg = v[1];
  s.pan_zero_deg = v[2];
  s.tilt_zero_deg = v[3];
  s.tilt_axis_offset_m = {v[4], v[5], v[6]};
  s.tilt_axis_skew_deg = v[7];
  s.rig_offset_m = {v[8], v[9], v[10]};
  s.rig_rotation_opk_deg = {v[11], v[12], v[13]};
  return s;
}

}  // namespace ts
