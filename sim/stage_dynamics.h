#pragma once
// One simulated stage axis: trapezoidal motion (speed and acceleration limits), a settling
// time with a decaying wobble, a small positioning error at each target (repeatable, as a
// real axis's is: so a simulator can know where a move will end before it starts), soft limits,
// homing, alarms, and the stall and alarm faults. Pure state machine: Step(dt) advances time, so it
// is tested without any clock or network.
#include <cstdint>
#include <random>

namespace ts::sim {

struct AxisSettings {
  double speed_deg_s = 60.0;
  double acceleration_deg_s2 = 180.0;
  double settle_s = 0.2;
  double min_deg = -1e9, max_deg = 1e9;  // soft limits
  double position_error_deg = 0.002;     // sigma of where a move really ends, over targets
  int stall_after_moves = -1;            // fault: the move after this many stalls (-1 = never)
  int alarm_after_moves = -1;            // fault: the move after this many raises an alarm
};

class AxisDynamics {
 public:
  AxisDynamics(const AxisSettings& settings, uint64_t seed);

  // Commands (what the command register does). False if refused (alarm or limit).
  bool Start(double target_deg, double speed_deg_s, double acceleration_deg_s2);
  void Home();
  void Stop();
  void ResetAlarm();
  void Step(double dt_s);

  double position_deg() const { return position_ + wobble_; }
  double target_deg() const { return target_; }
  // Where the axis will come to rest: the target plus this move's positioning error.
  double goal_deg() const { return goal_; }
  // Where a move to `target_deg` will end (what goal_deg() becomes when it starts).
  double RestingDeg(double target_deg) const;
  bool moving() const { return phase_ == Phase::kMoving || phase_ == Phase::kStalled; }
  bool in_position() const { return phase_ == Phase::kIdle && !alarm_; }
  bool settling() const { return phase_ == Phase::kSettling; }
  bool homed() const { return homed_; }
  bool alarm() const { return alarm_; }
  bool limit() const { return limit_; }
  uint16_t alarm_code() const { return alarm_code_; }
  int moves() const { return moves_; }

 private:
  enum class Phase { kIdle, kMoving, kSettling, kStalled };
  void BeginMove(double target, double speed, double acceleration);

  AxisSettings settings_;
  uint64_t seed_;
  std::mt19937_64 rng_;
  Phase phase_ = Phase::kIdle;
  double position_ = 0.0, velocity_ = 0.0, wobble_ = 0.0;
  double target_ = 0.0, goal_ = 0.0,
         start_ = 0.0;  // goal: where this move really ends (target + error)
  double speed_ = 60.0, acceleration_ = 180.0, settle_left_s_ = 0.0;
  bool homed_ = false, alarm_ = false, limit_ = false, homing_ = false;
  uint16_t alarm_code_ = 0;
  int moves_ = 0;
};

}  // namespace ts::sim
