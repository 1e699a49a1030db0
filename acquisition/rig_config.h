#pragma once
// The rig config (RIG.yaml): which devices make up a rig and their calibration.
//
//   schema_version: 1
//   name: paper-rig
//   calibration: {...}              # the calibration.yaml schema, inline, or
//   calibration_file: cal.yaml      # a path relative to this file
//   devices:
//     left_camera:  {id: TS-SIM-L, packet_size_bytes: 0}
//     right_camera: {id: TS-SIM-R}
//     stage: {transport: tcp, host: 127.0.0.1, port: 15020, unit_id: 1, inclinometer: pan}
//        or  {transport: rtu, device: /dev/topostation-stage, baud: 115200, parity: N,
//             rs485: false, unit_id: 1}
//   inclinometer: pan (default: it rides the pan platform, as on topostation's stage; capture
//   reads it at every pose and processing fits the levelling free of its index error) or base
//   (one reading, at the start).
#include <string>

#include "core/result.h"
#include "devices/endpoints.h"
#include "processing/geometry/calibration.h"

namespace ts {

inline constexpr int kRigConfigSchemaVersion = 1;

struct RigConfig {
  std::string name;
  std::string file;  // where it was read from
  Calibration calibration;
  CameraEndpoint left_camera;
  CameraEndpoint right_camera;
  StageEndpoint stage;
};

// Errors: "FILE: field.path: problem" (for an external calibration file, that file's name).
Result<RigConfig> LoadRigConfig(const std::string& file);

}  // namespace ts
