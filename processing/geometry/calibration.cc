#include "processing/geometry/calibration.h"

namespace ts {

const char* SideName(Side side) { return side == Side::kLeft ? "left" : "right"; }

bool Calibration::Check(std::string* why) const {
  std::string err;
  if (!rig.Check(&err))
    err = "stereo rig: " + err;
  else if (!stage.Check(&err))
    err = "stage: " + err;
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

Eigen::Isometry3d Calibration::LFromCamera(Side side, double pan_deg, double tilt_deg) const {
  const Eigen::Isometry3d s_from_camera =
      side == Side::kLeft ? rig.SFromLeftCamera() : rig.SFromRightCamera();
  return stage.LFromS(pan_deg, tilt_deg) * s_from_camera;
}

}  // namespace ts
