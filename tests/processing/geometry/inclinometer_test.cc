// The inclinometer that rides the pan: its model against the stage kinematics (gravity seen from
// the platform), and the levelling separated from its index error by readings round the circle.
#include "processing/geometry/inclinometer.h"

#include <gtest/gtest.h>

#include <random>

namespace ts {
namespace {

StageKinematics Levelled(double x_deg, double y_deg, double pan_zero_deg) {
  StageKinematics s;
  s.levelling_x_deg = x_deg;
  s.levelling_y_deg = y_deg;
  s.pan_zero_deg = pan_zero_deg;
  return s;
}

// At true pan 0 it reads the levelling; turned by 90 deg clockwise, the tilt about its X axis is
// the base's about Y with the sign the kinematics give: the platform's Z axis in L, seen from
// the platform's own axes.
TEST(Inclinometer, ReadsThePlatformsTiltAsTheKinematicsTurnIt) {
  const StageKinematics s = Levelled(0.3, -0.2, 1.5);
  const Eigen::Vector2d index(0.01, -0.02);
  EXPECT_LT((InclinometerReads(s, 1.5, index) - Eigen::Vector2d(0.3, -0.2) - index).norm(), 1e-9);
  for (double pan : {0.0, 37.0, 90.0, 181.0, 300.0}) {
    // The platform's "up" in L from the kinematics, against the reading's own account of it.
    const Eigen::Matrix3d platform = s.LFromS(pan, 0.0).linear();  // rig mount is identity
    const Eigen::Vector2d r = InclinometerReads(s, pan, Eigen::Vector2d::Zero()) * M_PI / 180;
    const Eigen::Vector3d g_platform(std::cos(r.x()) * std::sin(r.y()), -std::sin(r.x()),
                                     -std::cos(r.x()) * std::cos(r.y()));
    EXPECT_LT((platform * g_platform - Eigen::Vector3d(0, 0, -1)).norm(), 1e-9) << pan;
  }
}

// Twelve pans 30 deg apart, readings with 0.002 deg noise and an index error of 0.02 deg: the
// levelling within its sigma (RMS of error over sigma near 1 over 200 draws), its sigma near
// 0.002 / sqrt(6); one reading alone is off by the index error.
TEST(Inclinometer, ReadingsRoundTheCircleSeparateTheLevellingFromTheIndexError) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.002), index(0.0, 0.02), level(0.0, 0.3);
  double sum_z2 = 0.0, worst_single = 0.0;
  int count = 0;
  for (int draw = 0; draw < 200; ++draw) {
    const StageKinematics truth = Levelled(level(rng), level(rng), 1.0 * index(rng) / 0.02);
    const Eigen::Vector2d index_error(index(rng), index(rng));
    std::vector<InclinometerReading> readings;
    for (int k = 0; k < 12; ++k) {
      const double pan = 30.0 * k + 0.01 * draw;
      readings.push_back({pan, InclinometerReads(truth, pan, index_error) +
                                   Eigen::Vector2d(noise(rng), noise(rng))});
    }
    const std::optional<LevellingFit> fit = FitLevelling(readings, truth, 0.002);
    ASSERT_TRUE(fit);
    EXPECT_NEAR(fit->levelling_sigma_deg, 0.002 / std::sqrt(6.0), 0.0004);
    const Eigen::Vector2d error =
        fit->levelling_deg - Eigen::Vector2d(truth.levelling_x_deg, truth.levelling_y_deg);
    sum_z2 += error.squaredNorm() / std::pow(fit->levelling_sigma_deg, 2);
    count += 2;
    EXPECT_LT((fit->index_error_deg - index_error).norm(), 0.005);
    worst_single = std::max(
        worst_single,
        (readings[0].tilt_deg - Eigen::Vector2d(truth.levelling_x_deg, truth.levelling_y_deg))
            .norm());
  }
  EXPECT_NEAR(std::sqrt(sum_z2 / count), 1.0, 0.15);
  EXPECT_GT(worst_single, 0.03);  // what the station knew from one reading
}

// Readings that cannot turn the levelling against the index error give no fit: too few, or all
// from one side of the circle.
TEST(Inclinometer, NoFitWithoutPansRoundTheCircle) {
  const StageKinematics s = Levelled(0.1, 0.1, 0.0);
  auto at = [&](std::vector<double> pans) {
    std::vector<InclinometerReading> r;
    for (double p : pans) r.push_back({p, InclinometerReads(s, p, Eigen::Vector2d::Zero())});
    return FitLevelling(r, s, 0.002);
  };
  EXPECT_FALSE(at({0, 180}));
  EXPECT_FALSE(at({0, 20, 40, 55}));
  EXPECT_TRUE(at({0, 120, 240}));
  EXPECT_TRUE(at({350, 40, 90, 150}));
}

}  // namespace
}  // namespace ts
