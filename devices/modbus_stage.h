#pragma once
// The stage over Modbus (libmodbus): RTU on a serial line or TCP, the register map of
// core/stage_registers.h. libmodbus never re-sends a request, so every
// transaction is retried here on a CRC error, a timeout or a garbled reply; moves are absolute
// and idempotent, so a retried write is harmless, and each is confirmed by reading back.
#include <chrono>
#include <memory>

#include "core/options.h"
#include "devices/endpoints.h"
#include "devices/stage.h"

namespace ts {

struct ModbusStageOptions {
  int retries = 5;
  std::chrono::milliseconds response_timeout{300};
  std::chrono::milliseconds poll_interval{20};
  std::chrono::milliseconds stall_time{1000};
  double stall_progress_deg = 0.01;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("retries", self.retries, {"per transaction, after the first attempt", "", 0, 100});
    v("response_timeout", self.response_timeout, {"a reply may take this long", "ms", 1, 60000});
    v("poll_interval", self.poll_interval, {"status poll while moving", "ms", 1, 10000});
    v("stall_time", self.stall_time,
      {"MOVING without progress this long is a stall", "ms", 1, 600000});
    v("stall_progress_deg", self.stall_progress_deg,
      {"less motion than this is no progress", "deg", 1e-6, 10});
  }
  bool Check(std::string* why) const;
};

// Connects; the error names the endpoint. RS-485 mode on a line that does not support it
// (ENOTTY, e.g. a pseudo-terminal) is reported in the log, not fatal.
Result<std::unique_ptr<Stage>> OpenModbusStage(const StageEndpoint& endpoint,
                                               const ModbusStageOptions& options = {});

}  // namespace ts
