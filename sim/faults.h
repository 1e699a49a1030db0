#pragma once
// Fault injection for `sim serve --faults key=value[,key=value...]` (DESIGN.md "Simulator"):
//   gvsp-loss=RATIO                      GVSP packets lost (the fake camera's own mechanism)
//   camera-gone=SIDE:after=S:for=S       a camera leaves the network for a while (seconds)
//   stage-stall=AXIS:after=MOVES         the move after MOVES moves of that axis stalls
//   stage-alarm=AXIS:after=MOVES         the move after MOVES moves trips an overload alarm
//   modbus-crc=RATIO                     replies corrupted (RTU: bad CRC; TCP: bad header)
//   modbus-drop=RATIO                    requests never answered
// An unknown key, a missing part or a value out of range is an error naming it.
#include <optional>
#include <string>

#include "core/result.h"
#include "processing/geometry/calibration.h"

namespace ts::sim {

struct CameraGoneFault {
  Side side = Side::kRight;
  double after_s = 0.0;
  double for_s = 0.0;
};

struct AxisFault {
  bool pan = true;  // false: tilt
  int after_moves = 0;
};

struct SimFaults {
  double gvsp_loss = 0.0;
  std::optional<CameraGoneFault> camera_gone;
  std::optional<AxisFault> stage_stall;
  std::optional<AxisFault> stage_alarm;
  double modbus_crc = 0.0;
  double modbus_drop = 0.0;
};

Result<SimFaults> ParseFaults(const std::string& spec);

}  // namespace ts::sim
