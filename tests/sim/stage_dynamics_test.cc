#include "sim/stage_dynamics.h"

#include <gtest/gtest.h>

#include "core/stage_registers.h"

namespace ts::sim {
namespace {

// Steps until the axis is at rest; returns the time taken.
double RunUntilIdle(AxisDynamics& axis, double limit_s = 30.0) {
  double t = 0.0;
  do {
    axis.Step(0.001);
    t += 0.001;
  } while ((axis.moving() || axis.settling()) && t < limit_s);
  return t;
}

TEST(AxisDynamics, TrapezoidalMoveTakesTheAnalyticTime) {
  AxisSettings s;
  s.position_error_deg = 0.0;
  AxisDynamics axis(s, 1);
  axis.Home();
  RunUntilIdle(axis);
  ASSERT_TRUE(axis.homed());
  ASSERT_TRUE(axis.Start(90.0, 60.0, 180.0));
  const double t = RunUntilIdle(axis);
  // Accelerate 1/3 s, cruise, decelerate 1/3 s: d/v + v/a = 1.5 + 0.333; then settle 0.2 s.
  EXPECT_NEAR(t, 1.5 + 1.0 / 3.0 + 0.2, 0.02);
  EXPECT_NEAR(axis.position_deg(), 90.0, 1e-9);
  EXPECT_TRUE(axis.in_position());
  // A short move never reaches full speed: 2 sqrt(d/a).
  ASSERT_TRUE(axis.Start(95.0, 60.0, 180.0));
  EXPECT_NEAR(RunUntilIdle(axis), 2 * std::sqrt(5.0 / 180.0) + 0.2, 0.02);
}

TEST(AxisDynamics, PositioningErrorIsSmallAndRandom) {
  AxisDynamics axis(AxisSettings{}, 4);
  double sum2 = 0.0;
  for (int i = 1; i <= 50; ++i) {
    ASSERT_TRUE(axis.Start(10.0 * i, 60, 180));
    RunUntilIdle(axis);
    sum2 += std::pow(axis.position_deg() - 10.0 * i, 2);
  }
  EXPECT_NEAR(std::sqrt(sum2 / 50), 0.002, 0.001);
}

// A simulator renders a view before the stage gets there: the axis must tell where a move
// will end, and end there, again and again (a real axis's error repeats at a target too).
TEST(AxisDynamics, AMoveEndsWhereRestingDegSaidAtEveryReturn) {
  AxisDynamics axis(AxisSettings{}, 9);
  for (double target : {30.0, -60.0, 30.0, 90.0, -60.0}) {
    const double predicted = axis.RestingDeg(target);
    EXPECT_NE(predicted, target);
    ASSERT_TRUE(axis.Start(target, 60, 180));
    EXPECT_EQ(axis.goal_deg(), predicted);
    RunUntilIdle(axis);
    EXPECT_EQ(axis.position_deg(), predicted) << target;
  }
  EXPECT_EQ(axis.RestingDeg(30.0), axis.RestingDeg(30.0));
  EXPECT_NE(AxisDynamics(AxisSettings{}, 10).RestingDeg(30.0), axis.RestingDeg(30.0));
}

TEST(AxisDynamics, SoftLimitRaisesAnAlarmUntilReset) {
  AxisSettings s;
  s.min_deg = -32;
  s.max_deg = 32;
  AxisDynamics axis(s, 1);
  EXPECT_FALSE(axis.Start(40.0, 30, 180));
  EXPECT_TRUE(axis.alarm() && axis.limit());
  EXPECT_EQ(axis.alarm_code(), stage_registers::kLimitAlarm);
  EXPECT_FALSE(axis.Start(10.0, 30, 180));  // refused while in alarm
  axis.ResetAlarm();
  EXPECT_TRUE(axis.Start(10.0, 30, 180));
}

TEST(AxisDynamics, StallAndAlarmFaults) {
  AxisSettings stall;
  stall.stall_after_moves = 1;
  AxisDynamics a(stall, 1);
  ASSERT_TRUE(a.Start(20, 60, 180));
  RunUntilIdle(a);
  const double before = a.position_deg();
  ASSERT_TRUE(a.Start(60, 60, 180));
  for (int i = 0; i < 2000; ++i) a.Step(0.001);
  EXPECT_TRUE(a.moving());
  EXPECT_DOUBLE_EQ(a.position_deg(), before);  // nothing turns
  a.Stop();
  EXPECT_FALSE(a.moving());

  AxisSettings trip;
  trip.alarm_after_moves = 0;
  AxisDynamics b(trip, 1);
  const double start = b.position_deg();
  ASSERT_TRUE(b.Start(start + 100, 60, 180));
  RunUntilIdle(b);
  EXPECT_TRUE(b.alarm());
  EXPECT_EQ(b.alarm_code(), stage_registers::kOverload);
  EXPECT_NEAR(b.position_deg() - start, 50.0, 2.0);  // tripped halfway
}

}  // namespace
}  // namespace ts::sim
