#pragma once
// Kinematics of the 2-axis rotary stage: the pose of the rig frame S in the station frame L
// for encoder readings (pan, tilt). DESIGN.md "Frames and geometry":
//
//   L_from_S(pan, tilt) = levelling * pan rotation * mount offsets * tilt rotation * rig mount
//
// Station frame L: origin at the stage axes, Z up along gravity, Y the horizontal direction of
// pan = 0, X = Y x Z. Pan is clockwise seen from above (so with Y north, pan is an azimuth),
// tilt positive upward. Every offset and small angle below is a rig-calibration parameter;
// all are zero for an ideal stage. The station mark is at (0, 0, -height_above_mark_m).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <numbers>
#include <string>

#include "core/result.h"
#include "processing/geometry/rotation.h"

namespace ts {

struct StageKinematics {
  // Levelling error of the pan axis: small rotations of the stage base about L's X, then Y.
  double levelling_x_deg = 0.0;
  double levelling_y_deg = 0.0;
  // Encoder readings at which the true angles are zero (encoder zero offsets).
  double pan_zero_deg = 0.0;
  double tilt_zero_deg = 0.0;
  // Mount offsets between the pan and the tilt axis, in the pan-rotated frame: position of the
  // tilt axis (m) and its skew from perpendicular to the pan axis (rotation about Y, deg).
  Eigen::Vector3d tilt_axis_offset_m = Eigen::Vector3d::Zero();
  double tilt_axis_skew_deg = 0.0;
  // Rig mounting on the tilt plate: S origin in the tilted frame (m) and the rotation of S in
  // it as omega-phi-kappa (deg, see rotation.h).
  Eigen::Vector3d rig_offset_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rig_rotation_opk_deg = Eigen::Vector3d::Zero();
  // Height of L's origin above the station mark (m). A crew tapes to the tilt axis (its
  // trunnion mark on the stage, as a theodolite's instrument height): SetInstrumentHeight.
  double height_above_mark_m = 0.0;

  bool Check(std::string* why) const;

  // Pose of S in L for encoder readings in degrees.
  Eigen::Isometry3d LFromS(double pan_deg, double tilt_deg) const;
  Eigen::Vector3d StationMarkInL() const { return {0.0, 0.0, -height_above_mark_m}; }
  // The instrument height: the tilt axis above the mark. L's origin lies tilt_axis_offset_m.z()
  // below the tilt axis, a height no image shows (it lifts every view alike), so only the taped
  // instrument height places the mark; the two heights move together.
  double InstrumentHeightM() const { return height_above_mark_m + tilt_axis_offset_m.z(); }
  // Refused (naming both heights) where the tilt axis would stand lower above the mark than
  // above L's origin: the mark would be above the stage.
  Status SetInstrumentHeight(double instrument_height_m);
};

// The calibration parameters as one vector (everything but the height above the mark), for
// adjustments; the names as in calibration.yaml's stage block.
inline constexpr int kStageParameterCount = 14;
using StageVector = std::array<double, kStageParameterCount>;
extern const char* const kStageParameterNames[kStageParameterCount];
StageVector StageVectorOf(const StageKinematics& stage);
// `stage` with the parameters of `v` (its height above the mark kept).
StageKinematics StageKinematicsOf(const StageVector& v, const StageKinematics& stage);

// The sigma (deg) of the angle by which the stage parameters' sigmas tilt a line of sight in
// elevation, averaged over the pan: the levelling about x and y (a line along one of them sees
// half of each, on average), the tilt axis's zero and the rig's pitch on its plate (omega)
// whole. Independent, as an adjustment's sigmas are taken here.
double SightTiltSigmaDeg(const StageVector& sigma);

// L_from_S as a rotation and a translation for a StageVector `v`; templated so that Ceres can
// differentiate it. StageKinematics::LFromS is this for doubles.
template <typename T>
void LFromSOf(const T* v, const T& pan_deg, const T& tilt_deg, Eigen::Matrix<T, 3, 3>* rotation,
              Eigen::Matrix<T, 3, 1>* translation) {
  const T rad(std::numbers::pi / 180.0);
  const Eigen::Matrix<T, 3, 3> levelling = RotationX(v[0] * rad) * RotationY(v[1] * rad);
  // Clockwise from above = negative rotation about +Z.
  const Eigen::Matrix<T, 3, 3> pan = RotationZ(-(pan_deg - v[2]) * rad);
  const Eigen::Matrix<T, 3, 3> skew = RotationY(v[7] * rad);
  // Positive tilt raises +Y towards +Z: positive rotation about +X.
  const Eigen::Matrix<T, 3, 3> tilt = RotationX((tilt_deg - v[3]) * rad);
  const Eigen::Matrix<T, 3, 3> rig = RotationFromOpkDeg(v[11], v[12], v[13]);
  const Eigen::Matrix<T, 3, 1> tilt_axis(v[4], v[5], v[6]), rig_offset(v[8], v[9], v[10]);
  // levelling * pan * (skew, tilt_axis) * tilt * (rig, rig_offset)
  const Eigen::Matrix<T, 3, 3> base = levelling * pan;
  const Eigen::Matrix<T, 3, 3> tilted = skew * tilt;
  *rotation = base * tilted * rig;
  *translation = base * (tilt_axis + tilted * rig_offset);
}

}  // namespace ts
