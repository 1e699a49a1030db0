#include "devices/modbus_stage.h"

#include <modbus/modbus.h>

#include <cerrno>
#include <cmath>
#include <thread>

#include "core/log.h"
#include "core/seconds.h"
#include "core/stage_registers.h"

namespace ts {

namespace reg = stage_registers;
using Clock = std::chrono::steady_clock;

const char* AxisName(Axis axis) { return axis == Axis::kPan ? "pan" : "tilt"; }
bool AxisState::homed() const { return status & reg::kHomed; }
bool AxisState::moving() const { return status & reg::kMoving; }
bool AxisState::in_position() const { return status & reg::kInPosition; }
bool AxisState::alarm() const { return status & reg::kAlarm; }

bool ModbusStageOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

namespace {

uint16_t Base(Axis axis) { return axis == Axis::kPan ? reg::kPanBase : reg::kTiltBase; }
int32_t Millidegrees(double deg) { return static_cast<int32_t>(std::lround(deg * 1000.0)); }

const char* AlarmName(uint16_t code) {
  switch (code) {
    case reg::kOverload:
      return "overload";
    case reg::kLimitAlarm:
      return "limit";
    case reg::kEncoder:
      return "encoder";
    case reg::kTimeout:
      return "timeout";
    default:
      return "unknown";
  }
}

class ModbusStage : public Stage {
 public:
  ModbusStage(modbus_t* ctx, std::string description, const ModbusStageOptions& options)
      : ctx_(ctx), description_(std::move(description)), options_(options) {}
  ~ModbusStage() override {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }

  std::string Describe() const override { return description_; }
  MoveTiming last_move_timing() const override { return last_move_timing_; }

  Result<StageInfo> Identify() override {
    uint16_t r[9];
    if (Status s = Read(reg::kModelId, 9, r); !s) return Error{s.error()};
    if (r[0] != reg::kModel)
      return Error{description_ + ": not a topostation stage (model id " + std::to_string(r[0]) +
                   ")"};
    StageInfo info;
    info.model_id = r[0];
    info.protocol_version = r[1];
    info.serial = reg::Join(r[2], r[3]);
    const double urad_to_deg = 1e-6 * 180.0 / M_PI;
    info.inclinometer_x_deg = static_cast<int32_t>(reg::Join(r[4], r[5])) * urad_to_deg;
    info.inclinometer_y_deg = static_cast<int32_t>(reg::Join(r[6], r[7])) * urad_to_deg;
    info.temperature_c = static_cast<int16_t>(r[8]) / 10.0;
    return info;
  }

  Result<AxisState> ReadAxis(Axis axis) override {
    uint16_t r[reg::kAxisRegisters];
    if (Status s = Read(Base(axis), reg::kAxisRegisters, r); !s) return Error{s.error()};
    AxisState state;
    state.position_deg =
        static_cast<int32_t>(reg::Join(r[reg::kActual], r[reg::kActual + 1])) / 1000.0;
    state.status = r[reg::kStatus];
    state.alarm_code = r[reg::kAlarmCode];
    return state;
  }

  Status Home(std::chrono::milliseconds timeout) override {
    for (Axis axis : {Axis::kPan, Axis::kTilt})
      if (Status s = Command(axis, reg::kHome); !s) return s;
    target_ = {0.0, 0.0};
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      std::this_thread::sleep_for(options_.poll_interval);
      if (interrupted()) return StopInterrupted();
      bool done = true;
      for (Axis axis : {Axis::kPan, Axis::kTilt}) {
        const Result<AxisState> a = ReadAxis(axis);
        if (!a) return Error{a.error()};
        if (a->alarm()) return AlarmError(axis, *a);
        done = done && a->homed() && a->in_position();
      }
      if (done) return {};
    }
    StopQuietly();
    return Error{description_ + ": homing did not finish in " + std::to_string(timeout.count()) +
                 " ms"};
  }

  Status StartMove(const StagePose& target) override {
    if (std::abs(target.tilt_deg) > reg::kTiltLimitDeg)
      return Error{description_ + ": tilt " + std::to_string(target.tilt_deg) +
                   " deg is beyond the +-32 deg limit"};
    target_ = target;
    for (Axis axis : {Axis::kPan, Axis::kTilt}) {
      const int32_t mdeg = Millidegrees(axis == Axis::kPan ? target.pan_deg : target.tilt_deg);
      const uint16_t words[2] = {reg::High(static_cast<uint32_t>(mdeg)),
                                 reg::Low(static_cast<uint32_t>(mdeg))};
      if (Status s = Write(Base(axis) + reg::kTarget, 2, words); !s) return s;
      uint16_t back[2];  // confirm: a corrupted write must not send the axis elsewhere
      if (Status s = Read(Base(axis) + reg::kTarget, 2, back); !s) return s;
      if (back[0] != words[0] || back[1] != words[1])
        return Error{description_ + ": " + AxisName(axis) + " target did not stick"};
      if (Status s = Command(axis, reg::kStart); !s) return s;
    }
    move_started_ = Clock::now();
    return {};
  }

  Result<StagePose> WaitInPosition(double tolerance_deg,
                                   std::chrono::milliseconds timeout) override {
    const auto deadline = Clock::now() + timeout;
    double last[2] = {NAN, NAN};
    Clock::time_point progress[2] = {Clock::now(), Clock::now()};
    // A START is taken within one stage cycle; before that the axis may still report the
    // previous IN_POSITION. Give it that cycle.
    std::this_thread::sleep_until(move_started_ + options_.poll_interval);
    Clock::time_point within_tolerance{};
    while (Clock::now() < deadline) {
      if (interrupted()) return StopInterrupted();
      bool done = true, near = true;
      StagePose pose;
      for (Axis axis : {Axis::kPan, Axis::kTilt}) {
        const int i = axis == Axis::kPan ? 0 : 1;
        const Result<AxisState> a = ReadAxis(axis);
        if (!a) return Error{a.error()};
        if (a->alarm()) return AlarmError(axis, *a);
        const double target = axis == Axis::kPan ? target_.pan_deg : target_.tilt_deg;
        (axis == Axis::kPan ? pose.pan_deg : pose.tilt_deg) = a->position_deg;
        const bool within = std::abs(a->position_deg - target) <= tolerance_deg;
        const bool arrived = a->in_position() && within;
        done = done && arrived;
        near = near && within;
        if (std::isnan(last[i]) ||
            std::abs(a->position_deg - last[i]) > options_.stall_progress_deg) {
          last[i] = a->position_deg;
          progress[i] = Clock::now();
        } else if (!arrived && a->moving() && Clock::now() - progress[i] > options_.stall_time) {
          StopQuietly();
          return Error{description_ + ": " + AxisName(axis) + " axis stalled at " +
                       std::to_string(a->position_deg) + " deg (target " + std::to_string(target) +
                       " deg); stage stopped"};
        }
      }
      const Clock::time_point now = Clock::now();
      if (near && within_tolerance == Clock::time_point{}) within_tolerance = now;
      if (done) {
        last_move_timing_ = {Seconds(within_tolerance - move_started_),
                             Seconds(now - within_tolerance)};
        return pose;
      }
      std::this_thread::sleep_for(options_.poll_interval);
    }
    StopQuietly();
    return Error{description_ + ": not in position after " + std::to_string(timeout.count()) +
                 " ms; stage stopped"};
  }

  Status Stop() override {
    Status result;
    for (Axis axis : {Axis::kPan, Axis::kTilt})
      if (Status s = Command(axis, reg::kStop); !s) result = s;
    return result;
  }

  Status ResetAlarms() override {
    for (Axis axis : {Axis::kPan, Axis::kTilt})
      if (Status s = Command(axis, reg::kAlarmReset); !s) return s;
    return {};
  }

 private:
  // Best effort on an error path: the error being reported matters more than this one.
  void StopQuietly() {
    if (Status s = Stop(); !s) {
    }
  }

  Error StopInterrupted() {
    StopQuietly();
    return Error{description_ + ": " + kInterruptedMessage};
  }

  Error AlarmError(Axis axis, const AxisState& a) {
    StopQuietly();
    return Error{description_ + ": " + AxisName(axis) + " axis alarm: " + AlarmName(a.alarm_code) +
                 " (code " + std::to_string(a.alarm_code) + ") at " +
                 std::to_string(a.position_deg) + " deg; stage stopped"};
  }

  // One transaction with retries on the errors a noisy line produces.
  template <typename Fn>
  Status Transact(const char* what, uint16_t address, Fn fn) {
    int last_errno = 0;
    for (int attempt = 0; attempt <= options_.retries; ++attempt) {
      if (fn()) return {};
      last_errno = errno;
      modbus_flush(ctx_);
      if (last_errno != EMBBADCRC && last_errno != ETIMEDOUT && last_errno != EMBBADDATA &&
          last_errno != EMBBADEXC && last_errno != EMBUNKEXC)
        break;
      if (attempt < options_.retries)
        Log().info("{}: {} of register 0x{} failed ({}), retrying", description_, what,
                   Hex(address), modbus_strerror(last_errno));
    }
    return Error{description_ + ": " + what + " of register 0x" + Hex(address) + " failed after " +
                 std::to_string(options_.retries + 1) +
                 " attempts: " + modbus_strerror(last_errno)};
  }
  Status Read(uint16_t address, int count, uint16_t* out) {
    return Transact("read", address,
                    [&] { return modbus_read_registers(ctx_, address, count, out) == count; });
  }
  Status Write(uint16_t address, int count, const uint16_t* words) {
    return Transact("write", address,
                    [&] { return modbus_write_registers(ctx_, address, count, words) == count; });
  }
  Status Command(Axis axis, uint16_t command) {
    const uint16_t address = Base(axis) + reg::kCommand;
    return Transact("command", address,
                    [&] { return modbus_write_register(ctx_, address, command) == 1; });
  }
  static std::string Hex(uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof(b), "%04X", v);
    return b;
  }

  modbus_t* ctx_;
  std::string description_;
  ModbusStageOptions options_;
  StagePose target_;
  Clock::time_point move_started_ = Clock::now();
  MoveTiming last_move_timing_;
};

}  // namespace

Result<std::unique_ptr<Stage>> OpenModbusStage(const StageEndpoint& e,
                                               const ModbusStageOptions& options) {
  std::string why;
  if (!e.Check(&why) || !options.Check(&why)) return Error{"stage: " + why};
  modbus_t* ctx = nullptr;
  std::string description;
  if (e.transport == StageTransport::kTcp) {
    ctx = modbus_new_tcp(e.host.c_str(), e.port);
    description = "stage (Modbus TCP " + e.host + ":" + std::to_string(e.port) + ")";
  } else {
    ctx = modbus_new_rtu(e.device.c_str(), e.baud, e.parity, 8, 1);
    description = "stage (Modbus RTU " + e.device + ")";
  }
  if (!ctx) return Error{description + ": cannot create context: " + modbus_strerror(errno)};
  modbus_set_slave(ctx, e.unit_id);
  const auto to = options.response_timeout;
  modbus_set_response_timeout(ctx, static_cast<uint32_t>(to.count() / 1000),
                              static_cast<uint32_t>((to.count() % 1000) * 1000));
  if (modbus_connect(ctx) != 0) {
    const std::string err = modbus_strerror(errno);
    modbus_free(ctx);
    return Error{description + ": cannot connect: " + err};
  }
  if (e.transport == StageTransport::kRtu && e.rs485 &&
      modbus_rtu_set_serial_mode(ctx, MODBUS_RTU_RS485) != 0) {
    const std::string err = modbus_strerror(errno);
    if (errno == ENOTTY) {  // a pseudo-terminal or an adapter without the ioctl: RS-232 framing
      Log().warn("{}: cannot switch to RS-485 ({}); going on without it", description, err);
    } else {
      modbus_close(ctx);
      modbus_free(ctx);
      return Error{description + ": cannot switch to RS-485: " + err};
    }
  }
  return std::unique_ptr<Stage>(new ModbusStage(ctx, description, options));
}

}  // namespace ts
