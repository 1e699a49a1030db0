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
#include <string>

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
  // Height of the stage centre above the station mark (m), measured in the field.
  double height_above_mark_m = 0.0;

  bool Check(std::string* why) const;

  // Pose of S in L for encoder readings in degrees.
  Eigen::Isometry3d LFromS(double pan_deg, double tilt_deg) const;
  Eigen::Vector3d StationMarkInL() const { return {0.0, 0.0, -height_above_mark_m}; }
};

}  // namespace ts
