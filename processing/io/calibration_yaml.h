#pragma once
// calibration.yaml: the stereo rig and stage kinematics, the file `process --calibration`
// reads, the simulator writes as truth, and `calibrate` writes. Schema (version 3; version 2
// is the same without stereo.joint_covariance, version 1 without the precision blocks; both
// still read, and a file is written as the lowest version that holds what it carries):
//
//   schema_version: 3
//   cameras:
//     left:                           # and right:, same fields
//       width_px: 1392
//       height_px: 1040
//       pixel_size_um: 6.45           # optional, 0 = unknown
//       principal_distance_px: 1860.5 # or principal_distance_mm (needs pixel_size_um)
//       principal_point_px: [695.5, 519.5]   # optional, default the image centre
//       distortion: {k1: 0, k2: 0, k3: 0, p1: 0, p2: 0}   # optional, dimensionless
//       affinity: {scale_x: 0, shear: 0}                   # optional
//       sigma: {c: 0.4, xp: 0.3, ...}    # optional, from a calibration: each parameter's
//       covariance: [100 numbers]         #   sigma and the 10 x 10 covariance (row-major,
//       rms_px: 0.21                      #   kParameterNames order), the RMS
//   stereo:
//     baseline_m: 0.5
//     left_rotation_opk_deg: [0, 0, 0]   # R_l relative to a camera looking along +Y_S
//     right_relative_opk_deg: [0, 0, 0]  # R = left_from_right (seed 003 eq. 2)
//     sigma: {baseline_m: 1e-4, right_relative_opk_deg: [0.002, 0.003, 0.001]}  # optional
//     covariance: [16 numbers]           # of baseline_m, omega phi kappa (deg)
//     rms_px: 0.25                       # over both images
//     joint_covariance: [576 numbers]    # optional (schema 3): both cameras and the pair
//                                        #   together, 24 x 24 (the left's ten, the right's,
//                                        #   then the four above); its diagonal blocks are the
//                                        #   three covariances
//   stage:                               # optional; every field defaults to the ideal stage
//     height_above_mark_m: 1.5           # L's origin: the instrument height taped to the tilt
//                                        #   axis, less tilt_axis_offset_m's z
//     levelling_deg: [0, 0]
//     pan_zero_deg: 0
//     tilt_zero_deg: 0
//     tilt_axis_offset_m: [0, 0, 0]
//     tilt_axis_skew_deg: 0
//     rig_offset_m: [0, 0, 0]
//     rig_rotation_opk_deg: [0, 0, 0]
#include <array>
#include <string>

#include "core/result.h"
#include "processing/geometry/calibration.h"
#include "processing/io/yaml_map.h"

namespace ts {

inline constexpr int kCalibrationSchemaVersion = 3;
// What a file without stereo.joint_covariance is written as: builds before schema 3 read it.
inline constexpr int kCalibrationSchemaWithoutJoint = 2;

// Errors: "FILE: field.path: problem".
Result<Calibration> LoadCalibrationYaml(const std::string& file);
// Parses a calibration mapping (the document root, or a block inside a rig config).
// Throws ConfigError with the field path.
Calibration ParseCalibration(YamlMap map);

std::string CalibrationToYaml(const Calibration& calibration);
// Written atomically (see atomic_file.h).
Status SaveCalibrationYaml(const Calibration& calibration, const std::string& file);

// One camera's calibration (`calibrate camera`): the fields of cameras.left above, with its
// precision, under `camera:` (schema 2).
//   schema_version: 2
//   camera: {width_px: 640, ..., sigma: {...}, covariance: [...], rms_px: 0.26}
std::string CameraCalibrationToYaml(const CameraIntrinsics& camera,
                                    const CameraPrecision& precision);
Result<CameraIntrinsics> LoadCameraCalibrationYaml(const std::string& file,
                                                   CameraPrecision* precision = nullptr);

}  // namespace ts
