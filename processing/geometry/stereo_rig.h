#pragma once
// The stereo camera bar in its rig frame S (seed 003, fig. 4 and eq. 2):
//   origin at the midpoint of the two projection centres, X along the baseline from the left
//   to the right centre, Y forward (viewing direction), Z up; right-handed.
//   T_l = (-B/2, 0, 0), T_r = -T_l, R_r = R_l * R   (seed 003 eq. 2)
// with R_l = S_from_left (rotation of the left camera frame into S) and R = left_from_right
// the relative orientation from stereo calibration. Camera frames follow camera_model.h
// (x right, y down, z forward), so a camera looking exactly along +Y_S with its rows
// horizontal has R_l = NominalSFromCamera().
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "processing/geometry/camera_model.h"

namespace ts {

struct StereoRig {
  CameraIntrinsics left;
  CameraIntrinsics right;
  double baseline_m = 0.0;                             // B, distance between the projection centres
  Eigen::Matrix3d S_from_left = NominalSFromCamera();  // R_l
  Eigen::Matrix3d left_from_right = Eigen::Matrix3d::Identity();  // R

  bool Check(std::string* why) const;

  // Camera-to-rig poses (rotation and projection centre in S).
  Eigen::Isometry3d SFromLeftCamera() const;
  Eigen::Isometry3d SFromRightCamera() const;
  // The left camera's frame to the right's (OpenCV's R, T: p_right = R p_left + T).
  Eigen::Isometry3d RightFromLeftCamera() const;

  // Rotation of a camera that looks along +Y_S with image x along +X_S and image y along -Z_S.
  static Eigen::Matrix3d NominalSFromCamera();

  // Builds the rig from a stereo calibration in OpenCV's convention, p_right = R p_left + t
  // (right_from_left). S is placed with X along the baseline and Y as close as possible to
  // the mean of the two viewing axes; Z completes the right-handed frame.
  static StereoRig FromStereoCalibration(const CameraIntrinsics& left,
                                         const CameraIntrinsics& right,
                                         const Eigen::Matrix3d& right_from_left_rotation,
                                         const Eigen::Vector3d& right_from_left_translation_m);
};

}  // namespace ts
