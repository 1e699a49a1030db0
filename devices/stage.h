#pragma once
// The 2-axis rotary stage, as the acquisition layer sees it. One implementation talks Modbus
// (modbus_stage.h); tests may put an in-process fake behind the same interface.
//
// Lifecycle: open (backend factory) -> Identify() -> Home() -> MoveTo()/StartMove()+
// WaitInPosition() ... -> destroy. Every call returns a Status/Result and never throws or
// aborts: a crash could leave the stage moving. Not thread-safe: one owner thread, except
// Interrupt(), which any thread may call (a job cancelled from the daemon's API).
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "core/result.h"
#include "core/stage_pose.h"

namespace ts {

enum class Axis { kPan, kTilt };
const char* AxisName(Axis axis);

struct StageInfo {
  uint16_t model_id = 0;
  uint16_t protocol_version = 0;
  uint32_t serial = 0;
  double inclinometer_x_deg = 0.0;  // levelling error the stage measures
  double inclinometer_y_deg = 0.0;
  double temperature_c = 0.0;
};

struct AxisState {
  double position_deg = 0.0;  // encoder reading
  uint16_t status = 0;        // stage_registers::StatusBit
  uint16_t alarm_code = 0;
  bool homed() const;
  bool moving() const;
  bool in_position() const;
  bool alarm() const;
};

// Where the time of the last move went, as the driver saw it (seconds; NaN when unknown).
struct MoveTiming {
  double moving_s = NAN;    // from the start command until both axes were within tolerance
  double settling_s = NAN;  // from then until both reported IN_POSITION
};

class Stage {
 public:
  virtual ~Stage() = default;
  virtual std::string Describe() const = 0;  // "Modbus TCP 127.0.0.1:15020 unit 1"
  virtual Result<StageInfo> Identify() = 0;
  virtual Result<AxisState> ReadAxis(Axis axis) = 0;
  // Homes both axes and waits until both report HOMED and IN_POSITION.
  virtual Status Home(std::chrono::milliseconds timeout) = 0;
  // Commands an absolute move of both axes (idempotent; confirmed by reading the targets back)
  // and returns without waiting.
  virtual Status StartMove(const StagePose& target) = 0;
  // Waits until both axes are IN_POSITION within tolerance of the last target; fails on an
  // alarm, a stall (no progress while MOVING) or the timeout, stopping the stage first.
  virtual Result<StagePose> WaitInPosition(double tolerance_deg,
                                           std::chrono::milliseconds timeout) = 0;
  virtual Status Stop() = 0;
  virtual Status ResetAlarms() = 0;
  // Of the last WaitInPosition() that succeeded.
  virtual MoveTiming last_move_timing() const { return {}; }

  // From any thread: the wait in progress (and every later Home or wait) stops the stage and
  // fails with kInterruptedMessage, within one status poll.
  void Interrupt() { interrupted_ = true; }
  bool interrupted() const { return interrupted_; }
  static constexpr const char* kInterruptedMessage = "interrupted: the stage was stopped";

  Result<StagePose> MoveTo(const StagePose& target, double tolerance_deg,
                           std::chrono::milliseconds timeout) {
    if (Status s = StartMove(target); !s) return Error{s.error()};
    return WaitInPosition(tolerance_deg, timeout);
  }

 private:
  std::atomic<bool> interrupted_{false};
};

}  // namespace ts
