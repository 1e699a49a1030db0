// A libmodbus client drives the simulated stage through move, home and alarm cycles, over
// Modbus TCP on loopback and Modbus RTU on the simulator's pseudo-terminal.
#include <gtest/gtest.h>
#include <modbus/modbus.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "core/stage_registers.h"
#include "processing/geometry/inclinometer.h"
#include "sim/simulated_stage.h"

namespace ts::sim {
namespace {

namespace reg = stage_registers;
using Clock = std::chrono::steady_clock;

class Client {
 public:
  explicit Client(modbus_t* ctx) : ctx_(ctx) {
    modbus_set_slave(ctx_, 1);
    modbus_set_response_timeout(ctx_, 0, 300000);
    EXPECT_EQ(modbus_connect(ctx_), 0) << modbus_strerror(errno);
  }
  ~Client() {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  // Reads with a few retries (the fault tests make single reads fail on purpose).
  uint16_t Read(uint16_t address) {
    uint16_t v = 0;
    for (int i = 0; i < 5; ++i)
      if (modbus_read_registers(ctx_, address, 1, &v) == 1) return v;
    ADD_FAILURE() << "read " << address << ": " << modbus_strerror(errno);
    return 0;
  }
  int32_t Read32(uint16_t address) {
    uint16_t v[2] = {0, 0};
    EXPECT_EQ(modbus_read_registers(ctx_, address, 2, v), 2) << modbus_strerror(errno);
    return static_cast<int32_t>(reg::Join(v[0], v[1]));
  }
  void Write32(uint16_t address, int32_t value) {
    const uint16_t v[2] = {reg::High(static_cast<uint32_t>(value)),
                           reg::Low(static_cast<uint32_t>(value))};
    EXPECT_EQ(modbus_write_registers(ctx_, address, 2, v), 2) << modbus_strerror(errno);
  }
  void Command(uint16_t base, uint16_t command) {
    EXPECT_EQ(modbus_write_register(ctx_, base + reg::kCommand, command), 1);
  }
  // Waits until all `bits` are set in the axis status; returns seconds waited (< 0: timeout).
  double WaitFor(uint16_t base, uint16_t bits, double timeout_s = 10.0) {
    const auto t0 = Clock::now();
    while (std::chrono::duration<double>(Clock::now() - t0).count() < timeout_s) {
      if ((Read(base + reg::kStatus) & bits) == bits)
        return std::chrono::duration<double>(Clock::now() - t0).count();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1.0;
  }
  modbus_t* ctx() { return ctx_; }

 private:
  modbus_t* ctx_;
};

void FullCycle(Client& c, const SimulatedStageOptions& options) {
  EXPECT_EQ(c.Read(reg::kModelId), reg::kModel);
  EXPECT_EQ(c.Read(reg::kProtocolVersion), reg::kVersion);
  // The inclinometer rides the pan: it reads the levelling turned by the pan, and its index
  // error.
  auto reads = [&](double pan_deg, uint16_t address) {
    const Eigen::Vector2d deg =
        InclinometerReads(options.levelling, pan_deg, options.inclinometer_index_error_deg);
    return deg[address == reg::kInclinometerX ? 0 : 1] * M_PI / 180 * 1e6;
  };
  const double unhomed_pan = static_cast<int32_t>(c.Read32(reg::kPanBase + reg::kActual)) / 1000.0;
  for (uint16_t address : {reg::kInclinometerX, reg::kInclinometerY})
    EXPECT_NEAR(static_cast<int32_t>(c.Read32(address)), reads(unhomed_pan, address), 1);
  // Home both axes.
  c.Command(reg::kPanBase, reg::kHome);
  c.Command(reg::kTiltBase, reg::kHome);
  ASSERT_GE(c.WaitFor(reg::kPanBase, reg::kHomed | reg::kInPosition | reg::kReady), 0.0);
  ASSERT_GE(c.WaitFor(reg::kTiltBase, reg::kHomed | reg::kInPosition), 0.0);
  EXPECT_EQ(c.Read32(reg::kPanBase + reg::kActual), 0);
  EXPECT_EQ(c.Read(reg::kPanBase + reg::kCommand), 0);  // taken
  // Absolute move: pan 90 deg at 60 deg/s, 180 deg/s^2 takes 1.83 s plus 0.2 s settling.
  c.Write32(reg::kPanBase + reg::kTarget, 90000);
  const auto t0 = Clock::now();
  c.Command(reg::kPanBase, reg::kStart);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_TRUE(c.Read(reg::kPanBase + reg::kStatus) & reg::kMoving);
  ASSERT_GE(c.WaitFor(reg::kPanBase, reg::kInPosition), 0.0);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_NEAR(seconds, 2.03, 0.3);
  EXPECT_NEAR(c.Read32(reg::kPanBase + reg::kActual), 90000, 10);
  const double pan = static_cast<int32_t>(c.Read32(reg::kPanBase + reg::kActual)) / 1000.0;
  for (uint16_t address : {reg::kInclinometerX, reg::kInclinometerY})  // turned with the pan
    EXPECT_NEAR(static_cast<int32_t>(c.Read32(address)), reads(pan, address), 1);
  // Tilt beyond its soft limit: alarm, limit, code 2; nothing moves; reset clears it.
  c.Write32(reg::kTiltBase + reg::kTarget, 40000);
  c.Command(reg::kTiltBase, reg::kStart);
  ASSERT_GE(c.WaitFor(reg::kTiltBase, reg::kAlarm | reg::kLimit, 2.0), 0.0);
  EXPECT_EQ(c.Read(reg::kTiltBase + reg::kAlarmCode), reg::kLimitAlarm);
  EXPECT_EQ(c.Read32(reg::kTiltBase + reg::kActual), 0);
  c.Command(reg::kTiltBase, reg::kAlarmReset);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(c.Read(reg::kTiltBase + reg::kStatus) & reg::kAlarm, 0);
  EXPECT_EQ(c.Read(reg::kTiltBase + reg::kAlarmCode), reg::kNoAlarm);
  // A legal tilt move still works after the reset.
  c.Write32(reg::kTiltBase + reg::kTarget, -17000);
  c.Command(reg::kTiltBase, reg::kStart);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_GE(c.WaitFor(reg::kTiltBase, reg::kInPosition), 0.0);
  EXPECT_NEAR(c.Read32(reg::kTiltBase + reg::kActual), -17000, 10);
}

TEST(SimulatedStage, FullCycleOverModbusTcp) {
  SimulatedStageOptions options;
  options.levelling.levelling_x_deg = 0.12;
  options.inclinometer_index_error_deg = {0.01, -0.02};
  SimulatedStage stage(options);
  ASSERT_TRUE(stage.ListenTcp("127.0.0.1", 15121).ok());
  Client client(modbus_new_tcp("127.0.0.1", 15121));
  FullCycle(client, options);
  EXPECT_NEAR(stage.Pose().pan_deg, 90.0, 0.02);
}

TEST(SimulatedStage, FullCycleOverModbusRtuOnAPseudoTerminal) {
  SimulatedStageOptions options;
  options.levelling.levelling_x_deg = -0.2;
  options.levelling.pan_zero_deg = 0.7;
  SimulatedStage stage(options);
  const Result<std::string> pty = stage.ServePty();
  ASSERT_TRUE(pty.ok()) << pty.error();
  modbus_t* ctx = modbus_new_rtu(pty->c_str(), 115200, 'N', 8, 1);
  // RS-485 mode is an ioctl a pseudo-terminal does not have: ENOTTY, which is not fatal.
  Client client(ctx);
  EXPECT_EQ(modbus_rtu_set_serial_mode(ctx, MODBUS_RTU_RS485), -1);
  FullCycle(client, options);
}

// The inclinometer's noise is drawn anew with each move, not with each tick of the simulation:
// standing still it reads the same however often (and however late) it is read, so a survey
// of one seed reads the same whatever the machine's load; back at the same pose after a move,
// it reads another draw of the same size.
TEST(SimulatedStage, InclinometerNoiseIsDrawnPerMoveNotPerTick) {
  SimulatedStageOptions options;
  options.inclinometer_noise_deg = 0.002;
  SimulatedStage stage(options);
  ASSERT_TRUE(stage.ListenTcp("127.0.0.1", 15124).ok());
  Client c(modbus_new_tcp("127.0.0.1", 15124));
  auto home = [&] {
    c.Command(reg::kPanBase, reg::kHome);
    c.Command(reg::kTiltBase, reg::kHome);
    ASSERT_GE(c.WaitFor(reg::kPanBase, reg::kHomed | reg::kInPosition | reg::kReady), 0.0);
    ASSERT_GE(c.WaitFor(reg::kTiltBase, reg::kHomed | reg::kInPosition), 0.0);
  };
  // Microradians, as the registers hold them.
  auto reading = [&] {
    return std::pair{c.Read32(reg::kInclinometerX), c.Read32(reg::kInclinometerY)};
  };
  const double five_sigma_urad = 5 * options.inclinometer_noise_deg * M_PI / 180.0 * 1e6;
  home();
  const auto first = reading();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(reading(), first);
  // The levelling is zero: what it reads is its noise.
  EXPECT_NE(first, std::pair(0, 0));
  EXPECT_LT(std::max(std::abs(first.first), std::abs(first.second)), five_sigma_urad);
  c.Write32(reg::kPanBase + reg::kTarget, 10000);
  c.Command(reg::kPanBase, reg::kStart);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_GE(c.WaitFor(reg::kPanBase, reg::kInPosition), 0.0);
  home();
  const auto again = reading();
  EXPECT_NE(again, first);
  EXPECT_LT(std::max(std::abs(again.first), std::abs(again.second)), five_sigma_urad);
}

TEST(SimulatedStage, CorruptedAndDroppedRepliesAtTheRequestedRates) {
  SimulatedStageOptions options;
  options.corrupt_reply_ratio = 0.2;
  options.drop_reply_ratio = 0.1;
  SimulatedStage stage(options);
  const Result<std::string> pty = stage.ServePty();
  ASSERT_TRUE(pty.ok());
  modbus_t* ctx = modbus_new_rtu(pty->c_str(), 115200, 'N', 8, 1);
  modbus_set_slave(ctx, 1);
  modbus_set_response_timeout(ctx, 0, 100000);
  ASSERT_EQ(modbus_connect(ctx), 0);
  int ok = 0, bad_crc = 0, timeouts = 0;
  for (int i = 0; i < 300; ++i) {
    uint16_t v;
    if (modbus_read_registers(ctx, reg::kModelId, 1, &v) == 1) {
      ++ok;
      EXPECT_EQ(v, reg::kModel);
    } else if (errno == EMBBADCRC) {
      ++bad_crc;
    } else if (errno == ETIMEDOUT) {
      ++timeouts;
    }
    modbus_flush(ctx);
  }
  modbus_close(ctx);
  modbus_free(ctx);
  EXPECT_NEAR(timeouts / 300.0, 0.1, 0.06);
  EXPECT_NEAR(bad_crc / 300.0, 0.9 * 0.2, 0.07);
  EXPECT_EQ(ok + bad_crc + timeouts, 300);
}

TEST(SimulatedStage, AlarmAndStallFaults) {
  SimulatedStageOptions options;
  options.pan.alarm_after_moves = 1;
  options.tilt.stall_after_moves = 0;
  SimulatedStage stage(options);
  ASSERT_TRUE(stage.ListenTcp("127.0.0.1", 15122).ok());
  Client c(modbus_new_tcp("127.0.0.1", 15122));
  c.Write32(reg::kPanBase + reg::kTarget, 30000);
  c.Command(reg::kPanBase, reg::kStart);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_GE(c.WaitFor(reg::kPanBase, reg::kInPosition), 0.0);
  c.Write32(reg::kPanBase + reg::kTarget, 90000);
  c.Command(reg::kPanBase, reg::kStart);
  ASSERT_GE(c.WaitFor(reg::kPanBase, reg::kAlarm, 5.0), 0.0);
  EXPECT_EQ(c.Read(reg::kPanBase + reg::kAlarmCode), reg::kOverload);
  EXPECT_NEAR(c.Read32(reg::kPanBase + reg::kActual), 60000, 2000);  // stopped halfway
  // The tilt stalls on its first move: MOVING stays set and the position never changes.
  const int32_t tilt0 = c.Read32(reg::kTiltBase + reg::kActual);
  c.Write32(reg::kTiltBase + reg::kTarget, -15000);
  c.Command(reg::kTiltBase, reg::kStart);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_TRUE(c.Read(reg::kTiltBase + reg::kStatus) & reg::kMoving);
  EXPECT_EQ(c.Read32(reg::kTiltBase + reg::kActual), tilt0);
}

}  // namespace
}  // namespace ts::sim
