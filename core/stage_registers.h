#pragma once
// The Modbus register map of the 2-axis rotary stage (DESIGN.md "Devices"): constants only,
// shared by the stage driver (devices/) and the simulated stage (sim/) so both speak exactly
// one protocol. Unit id 1, holding registers, 32-bit values as two registers, high word first.
#include <cstdint>

namespace ts::stage_registers {

// Device block.
inline constexpr uint16_t kModelId = 0x0000;          // u16
inline constexpr uint16_t kProtocolVersion = 0x0001;  // u16
inline constexpr uint16_t kSerial = 0x0002;           // u32
inline constexpr uint16_t kInclinometerX = 0x0004;    // s32, microradians
inline constexpr uint16_t kInclinometerY = 0x0006;    // s32, microradians
inline constexpr uint16_t kTemperature = 0x0008;      // s16, 0.1 degC

// Per axis, from the axis base.
inline constexpr uint16_t kPanBase = 0x0100;
inline constexpr uint16_t kTiltBase = 0x0200;
inline constexpr uint16_t kTarget = 0x00;        // s32, millidegrees
inline constexpr uint16_t kSpeed = 0x02;         // u32, millidegrees/s
inline constexpr uint16_t kAcceleration = 0x04;  // u32, millidegrees/s^2
inline constexpr uint16_t kCommand = 0x06;       // u16, reads 0 once taken
inline constexpr uint16_t kActual = 0x08;        // s32, millidegrees (read only)
inline constexpr uint16_t kStatus = 0x0A;        // u16 bits, below
inline constexpr uint16_t kAlarmCode = 0x0B;     // u16, below
inline constexpr uint16_t kAxisRegisters = 0x0C;
inline constexpr uint16_t kRegisterCount = kTiltBase + kAxisRegisters;

enum Command : uint16_t { kNone = 0, kStart = 1, kHome = 2, kStop = 3, kAlarmReset = 4 };
enum StatusBit : uint16_t {
  kReady = 1 << 0,
  kMoving = 1 << 1,
  kInPosition = 1 << 2,
  kHomed = 1 << 3,
  kAlarm = 1 << 4,
  kLimit = 1 << 5,
};
enum AlarmCode : uint16_t {
  kNoAlarm = 0,
  kOverload = 1,
  kLimitAlarm = 2,
  kEncoder = 3,
  kTimeout = 4
};

inline constexpr uint16_t kModel = 0x7501;  // topostation 2-axis stage
inline constexpr uint16_t kVersion = 1;
inline constexpr double kTiltLimitDeg = 32.0;

inline uint32_t Join(uint16_t high, uint16_t low) { return (uint32_t{high} << 16) | low; }
inline uint16_t High(uint32_t v) { return static_cast<uint16_t>(v >> 16); }
inline uint16_t Low(uint32_t v) { return static_cast<uint16_t>(v & 0xFFFF); }

}  // namespace ts::stage_registers
