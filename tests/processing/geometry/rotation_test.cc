#include "processing/geometry/rotation.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <numbers>
#include <random>

namespace ts {
namespace {

TEST(Rotation, ElementaryRotationsAreActiveAndRightHanded) {
  EXPECT_TRUE((RotationZ(std::numbers::pi / 2) * Eigen::Vector3d::UnitX())
                  .isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE((RotationX(std::numbers::pi / 2) * Eigen::Vector3d::UnitY())
                  .isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE((RotationY(std::numbers::pi / 2) * Eigen::Vector3d::UnitZ())
                  .isApprox(Eigen::Vector3d::UnitX()));
  for (const Eigen::Matrix3d& r : {RotationX(0.3), RotationY(-1.1), RotationZ(2.5)}) {
    EXPECT_NEAR((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-15);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
  }
}

TEST(Rotation, OpkRoundTrip) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> any(-std::numbers::pi, std::numbers::pi),
      half(-std::numbers::pi / 2 + 1e-3, std::numbers::pi / 2 - 1e-3);
  for (int i = 0; i < 1000; ++i) {
    const Opk in{any(rng), half(rng), any(rng)};
    const Opk out = OpkFromRotation(RotationFromOpk(in));
    EXPECT_NEAR(out.omega_rad, in.omega_rad, 1e-9);
    EXPECT_NEAR(out.phi_rad, in.phi_rad, 1e-9);
    EXPECT_NEAR(out.kappa_rad, in.kappa_rad, 1e-9);
  }
}

TEST(Rotation, OpkAtGimbalLockKeepsTheRotation) {
  for (double phi : {std::numbers::pi / 2, -std::numbers::pi / 2}) {
    const Eigen::Matrix3d r = RotationFromOpk({0.4, phi, -0.7});
    const Opk out = OpkFromRotation(r);
    EXPECT_DOUBLE_EQ(out.kappa_rad, 0.0);
    EXPECT_NEAR((RotationFromOpk(out) - r).norm(), 0.0, 1e-12);
  }
}

TEST(Rotation, AzElRollElementsOfSeed004) {
  const double t = 0.5, p = -0.2, k = 0.3;
  const Eigen::Matrix3d m = RotationFromAzElRoll({t, p, k});
  using std::cos, std::sin;
  EXPECT_NEAR(m(0, 0), cos(k) * cos(t) - sin(k) * sin(p) * sin(t), 1e-15);
  EXPECT_NEAR(m(0, 1), sin(k) * cos(p), 1e-15);
  EXPECT_NEAR(m(1, 2), sin(k) * sin(t) - cos(k) * sin(p) * cos(t), 1e-15);
  EXPECT_NEAR(m(2, 0), cos(p) * sin(t), 1e-15);
  EXPECT_NEAR(m(2, 1), sin(p), 1e-15);
  EXPECT_NEAR(m(2, 2), cos(p) * cos(t), 1e-15);
  // Eq. 3b is Rz(-kappa) Rx(phi) Ry(-theta): eq. 2a as printed has the opposite theta.
  EXPECT_NEAR((m - RotationZ(-k) * RotationX(p) * RotationY(-t)).norm(), 0.0, 1e-15);
  EXPECT_GT((m - RotationZ(-k) * RotationX(p) * RotationY(t)).norm(), 0.1);
  EXPECT_NEAR(m.determinant(), 1.0, 1e-14);
}

TEST(Rotation, AzElRollRoundTripAndGimbalLock) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> any(-std::numbers::pi, std::numbers::pi),
      half(-std::numbers::pi / 2 + 1e-3, std::numbers::pi / 2 - 1e-3);
  for (int i = 0; i < 1000; ++i) {
    const AzElRoll in{any(rng), half(rng), any(rng)};
    const AzElRoll out = AzElRollFromRotation(RotationFromAzElRoll(in));
    EXPECT_NEAR(out.azimuth_rad, in.azimuth_rad, 1e-9);
    EXPECT_NEAR(out.elevation_rad, in.elevation_rad, 1e-9);
    EXPECT_NEAR(out.roll_rad, in.roll_rad, 1e-9);
  }
  const Eigen::Matrix3d locked = RotationFromAzElRoll({0.3, std::numbers::pi / 2, 0.2});
  EXPECT_NEAR((RotationFromAzElRoll(AzElRollFromRotation(locked)) - locked).norm(), 0.0, 1e-12);
}

TEST(Rotation, ConvertsBetweenConventionsThroughTheMatrix) {
  const AzElRoll a{0.7, 0.25, -0.1};
  const Eigen::Matrix3d m = RotationFromAzElRoll(a);
  const Opk opk = OpkFromRotation(m);
  EXPECT_NEAR((RotationFromOpk(opk) - m).norm(), 0.0, 1e-12);
  const AzElRoll back = AzElRollFromRotation(RotationFromOpk(opk));
  EXPECT_NEAR(back.azimuth_rad, a.azimuth_rad, 1e-12);
  EXPECT_NEAR(back.elevation_rad, a.elevation_rad, 1e-12);
  EXPECT_NEAR(back.roll_rad, a.roll_rad, 1e-12);
}

TEST(Rotation, DegreesAndRadians) {
  EXPECT_DOUBLE_EQ(RadFromDeg(180.0), std::numbers::pi);
  EXPECT_DOUBLE_EQ(DegFromRad(std::numbers::pi / 2), 90.0);
}

}  // namespace
}  // namespace ts
