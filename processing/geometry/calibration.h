#pragma once
// Everything the pipeline needs to turn pixels into station-frame coordinates: the stereo
// rig (interior and relative orientation) and the stage kinematics (rig calibration).
// Read and written as calibration.yaml by processing/io/calibration_yaml.h.
#include <Eigen/Geometry>
#include <string>

#include "processing/geometry/stage_kinematics.h"
#include "processing/geometry/stereo_rig.h"

namespace ts {

enum class Side { kLeft, kRight };
const char* SideName(Side side);

struct Calibration {
  StereoRig rig;
  StageKinematics stage;

  bool Check(std::string* why) const;
  // Pose of a camera in L for the stage's encoder readings.
  Eigen::Isometry3d LFromCamera(Side side, double pan_deg, double tilt_deg) const;
};

}  // namespace ts
