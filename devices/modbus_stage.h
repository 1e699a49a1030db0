#pragma once
// The stage over Modbus (libmodbus): RTU on a serial line or TCP, the register map of
// core/stage_registers.h. libmodbus never re-sends a request, so every
// transaction is retried here on a CRC error, a timeout or a garbled reply; moves are absolute
// and idempotent, so a retried write is harmless, and each is confirmed by reading back.
#include <memory>

#include "devices/endpoints.h"
#include "devices/stage.h"

namespace ts {

struct ModbusStageOptions {
  int retries = 5;  // per transaction, after the first attempt
  std::chrono::milliseconds response_timeout{300};
  std::chrono::milliseconds poll_interval{20};
  std::chrono::milliseconds stall_time{1000};  // MOVING without progress this long = stall
  double stall_progress_deg = 0.01;
  bool Check(std::string* why) const;
};

// Connects; the error names the endpoint. RS-485 mode on a line that does not support it
// (ENOTTY, e.g. a pseudo-terminal) is reported in the log, not fatal.
Result<std::unique_ptr<Stage>> OpenModbusStage(const StageEndpoint& endpoint,
                                               const ModbusStageOptions& options = {});

}  // namespace ts
