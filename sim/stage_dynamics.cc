#include "sim/stage_dynamics.h"

#include <algorithm>
#include <cmath>

#include "core/stage_registers.h"
#include "sim/noise.h"

namespace ts::sim {

namespace reg = stage_registers;

AxisDynamics::AxisDynamics(const AxisSettings& settings, uint64_t seed)
    : settings_(settings), seed_(seed), rng_(seed) {
  speed_ = settings.speed_deg_s;
  acceleration_ = settings.acceleration_deg_s2;
  // The axis powers up somewhere near zero, not homed.
  position_ = goal_ = target_ = std::uniform_real_distribution<double>(-3.0, 3.0)(rng_);
}

void AxisDynamics::BeginMove(double target, double speed, double acceleration) {
  target_ = target;
  start_ = position_;
  goal_ = RestingDeg(target);
  speed_ = std::clamp(speed, 0.1, settings_.speed_deg_s * 1.5);
  acceleration_ = std::clamp(acceleration, 1.0, settings_.acceleration_deg_s2 * 1.5);
  ++moves_;
  if (settings_.stall_after_moves >= 0 && moves_ > settings_.stall_after_moves) {
    phase_ = Phase::kStalled;  // motor current flows, nothing turns
    velocity_ = 0.0;
    return;
  }
  phase_ = Phase::kMoving;
}

double AxisDynamics::RestingDeg(double target_deg) const {
  // A normal deviate (Box-Muller) hashed from the target at the register's millidegree.
  const int64_t millideg = std::llround(target_deg * 1000.0);
  const double u1 = 0.5 * (HashUnit(seed_, millideg, 1) + 1.0);
  const double u2 = 0.5 * (HashUnit(seed_, millideg, 2) + 1.0);
  const double normal = std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * M_PI * u2);
  return target_deg + settings_.position_error_deg * normal;
}

bool AxisDynamics::Start(double target, double speed, double acceleration) {
  if (alarm_) return false;
  if (target < settings_.min_deg || target > settings_.max_deg) {
    alarm_ = limit_ = true;
    alarm_code_ = reg::kLimitAlarm;
    return false;
  }
  homing_ = false;
  BeginMove(target, speed, acceleration);
  return true;
}

void AxisDynamics::Home() {
  if (alarm_) return;
  homing_ = true;
  BeginMove(0.0, settings_.speed_deg_s, settings_.acceleration_deg_s2);
  goal_ = 0.0;  // the index mark is exact
}

void AxisDynamics::Stop() {
  if (phase_ == Phase::kMoving) {
    // Decelerate to a stop: the new goal is the stopping point.
    const double stopping = velocity_ * std::abs(velocity_) / (2.0 * acceleration_);
    goal_ = target_ = position_ + stopping;
  } else if (phase_ == Phase::kStalled) {
    phase_ = Phase::kIdle;
    target_ = goal_ = position_;
  }
}

void AxisDynamics::ResetAlarm() {
  alarm_ = limit_ = false;
  alarm_code_ = reg::kNoAlarm;
}

void AxisDynamics::Step(double dt) {
  if (phase_ == Phase::kMoving) {
    if (settings_.alarm_after_moves >= 0 && moves_ > settings_.alarm_after_moves &&
        std::abs(position_ - start_) >= 0.5 * std::abs(goal_ - start_)) {
      // Overload halfway: the drive trips and the axis stops where it is.
      alarm_ = true;
      alarm_code_ = reg::kOverload;
      phase_ = Phase::kIdle;
      velocity_ = 0.0;
      target_ = goal_ = position_;
      settings_.alarm_after_moves = -1;  // one alarm per fault
      return;
    }
    const double remaining = goal_ - position_;
    const double direction = remaining >= 0.0 ? 1.0 : -1.0;
    const double stopping = velocity_ * velocity_ / (2.0 * acceleration_);
    double v = std::abs(velocity_);
    if (std::abs(remaining) <= stopping + v * dt)
      v = std::max(0.0, v - acceleration_ * dt);
    else
      v = std::min(speed_, v + acceleration_ * dt);
    velocity_ = direction * v;
    const double step = velocity_ * dt;
    if (std::abs(step) >= std::abs(remaining) || (v == 0.0 && std::abs(remaining) < 1e-3)) {
      position_ = goal_;
      velocity_ = 0.0;
      phase_ = Phase::kSettling;
      settle_left_s_ = settings_.settle_s;
      if (homing_) homed_ = true, homing_ = false;
    } else {
      position_ += step;
    }
  } else if (phase_ == Phase::kSettling) {
    settle_left_s_ -= dt;
    // A wobble that decays through the settling time (millidegrees, as a real axis rings).
    const double t = settings_.settle_s - settle_left_s_;
    wobble_ = 0.01 * std::exp(-t / (0.2 * settings_.settle_s)) * std::sin(2.0 * 3.14159 * 25.0 * t);
    if (settle_left_s_ <= 0.0) {
      wobble_ = 0.0;
      phase_ = Phase::kIdle;
    }
  }
}

}  // namespace ts::sim
