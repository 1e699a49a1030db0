#pragma once
// Everything the pipeline needs to turn pixels into station-frame coordinates: the stereo
// rig (interior and relative orientation) and the stage kinematics (rig calibration).
// Read and written as calibration.yaml by processing/io/calibration_yaml.h.
#include <Eigen/Geometry>
#include <array>
#include <string>

#include "processing/geometry/stage_kinematics.h"
#include "processing/geometry/stereo_rig.h"

namespace ts {

enum class Side { kLeft, kRight };
const char* SideName(Side side);

// What a calibration adjustment says of its own precision (calibrate camera / stereo), kept
// with the values so that later steps can weigh them; unknown for design values.
struct CameraPrecision {
  bool known = false;
  std::array<double, CameraIntrinsics::kNumParameters> sigma{};  // kParameterNames order
  Eigen::Matrix<double, CameraIntrinsics::kNumParameters, CameraIntrinsics::kNumParameters>
      covariance = decltype(covariance)::Zero();
  double rms_px = 0.0;
};

struct StereoPrecision {
  bool known = false;
  double baseline_sigma_m = 0.0;
  Eigen::Vector3d relative_sigma_deg = Eigen::Vector3d::Zero();  // right_relative_opk_deg
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // baseline_m, omega phi kappa (deg)
  double rms_px = 0.0;
  // Of the cameras and the pair together, from the one adjustment that calibrated them: the
  // left camera's parameters (CameraIntrinsics::kParameterNames), the right's, then baseline_m
  // and right_relative_opk_deg; 24 x 24, its diagonal blocks the three covariances. Empty:
  // unknown, the three taken as uncorrelated. A camera's principal point and the pair's angles
  // move its rays almost alike, so their errors are strongly correlated: apart, the same
  // sigmas allow combinations that no calibration of these images would give.
  Eigen::MatrixXd joint_covariance;
};

struct Calibration {
  StereoRig rig;
  StageKinematics stage;
  CameraPrecision left_precision, right_precision;
  StereoPrecision stereo_precision;

  bool Check(std::string* why) const;
  // Pose of a camera in L for the stage's encoder readings.
  Eigen::Isometry3d LFromCamera(Side side, double pan_deg, double tilt_deg) const;
};

}  // namespace ts
