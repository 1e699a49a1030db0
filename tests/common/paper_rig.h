#pragma once
// The rig of seed 003 (table 1) for tests: 1392 x 1040 px of 6.45 um, f = 12 mm, 0.5 m base,
// ideal lenses, principal point at the image centre.
#include "processing/geometry/calibration.h"
#include "processing/geometry/rotation.h"

namespace ts::testing {

inline CameraIntrinsics PaperCamera() {
  CameraIntrinsics c;
  c.width_px = 1392;
  c.height_px = 1040;
  c.pixel_size_um = 6.45;
  c.principal_distance_px = 12.0e3 / 6.45;
  c.principal_point_x_px = 695.5;
  c.principal_point_y_px = 519.5;
  return c;
}

inline Calibration PaperCalibration(double height_above_mark_m = 1.5) {
  Calibration cal;
  cal.rig.left = cal.rig.right = PaperCamera();
  cal.rig.baseline_m = 0.5;
  cal.stage.height_above_mark_m = height_above_mark_m;
  return cal;
}

// A rig as built: distorted lenses, slightly converging and rotated cameras.
inline StereoRig RealisticRig() {
  StereoRig rig;
  rig.left = rig.right = PaperCamera();
  rig.left.k1 = -0.08;
  rig.left.k2 = 0.05;
  rig.right.k1 = -0.07;
  rig.right.p1 = 2e-4;
  rig.right.principal_distance_px *= 1.003;
  rig.baseline_m = 0.5;
  rig.S_from_left = StereoRig::NominalSFromCamera() * RotationFromOpk({0.002, -0.003, 0.001});
  rig.left_from_right = RotationFromOpk({0.004, 0.01, -0.002});
  return rig;
}

}  // namespace ts::testing
