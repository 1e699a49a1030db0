#include "processing/geometry/stage_kinematics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "processing/geometry/calibration.h"
#include "processing/geometry/rotation.h"

namespace ts {
namespace {

Eigen::Vector3d Forward(const StageKinematics& s, double pan, double tilt) {
  return s.LFromS(pan, tilt).linear() * Eigen::Vector3d::UnitY();
}

TEST(StageKinematics, IdealStageAtZeroIsIdentity) {
  const StageKinematics s;
  EXPECT_TRUE(s.LFromS(0, 0).matrix().isApprox(Eigen::Matrix4d::Identity()));
}

TEST(StageKinematics, PanIsClockwiseFromAbove) {
  const StageKinematics s;
  // With L's Y north and X east, pan 90 looks east and pan 180 south.
  EXPECT_TRUE(Forward(s, 90, 0).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(Forward(s, 180, 0).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  const Eigen::Vector3d f = Forward(s, 30, 0);
  EXPECT_NEAR(f.x(), std::sin(RadFromDeg(30)), 1e-12);
  EXPECT_NEAR(f.y(), std::cos(RadFromDeg(30)), 1e-12);
}

TEST(StageKinematics, TiltIsPositiveUpward) {
  const StageKinematics s;
  const Eigen::Vector3d f = Forward(s, 0, -20);
  EXPECT_NEAR(f.z(), -std::sin(RadFromDeg(20)), 1e-12);
  EXPECT_NEAR(f.y(), std::cos(RadFromDeg(20)), 1e-12);
  // Tilt keeps the baseline (S's X) horizontal.
  EXPECT_NEAR((s.LFromS(40, 25).linear() * Eigen::Vector3d::UnitX()).z(), 0.0, 1e-12);
}

TEST(StageKinematics, EncoderZerosShiftTheReadings) {
  StageKinematics offset;
  offset.pan_zero_deg = 12.5;
  offset.tilt_zero_deg = -1.75;
  const StageKinematics ideal;
  EXPECT_TRUE(offset.LFromS(12.5 + 60, -1.75 - 15)
                  .matrix()
                  .isApprox(ideal.LFromS(60, -15).matrix(), 1e-12));
}

TEST(StageKinematics, LevellingTiltsThePanAxis) {
  StageKinematics s;
  s.levelling_x_deg = 0.3;
  s.levelling_y_deg = -0.4;
  // The pan axis (Z of the stage base) leans by the combined small angle, ~0.5 deg.
  const Eigen::Vector3d axis = s.LFromS(77, 0).linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(DegFromRad(std::acos(axis.z())), 0.5, 1e-4);
}

// The sigma of a line of sight's elevation, from the stage's sigmas: each parameter moved by
// its sigma alone, the forward direction's change in elevation, squared and averaged round the
// pan (at the lower row's tilt and level), summed over the parameters. Those that only turn or
// shift the views (pan zero, the rig's roll and yaw, the offsets) add nothing.
TEST(StageKinematics, SightTiltSigmaIsWhatTheSigmasTiltTheLinesOfSightBy) {
  StageVector sigma{};
  sigma[0] = 0.01, sigma[1] = 0.02, sigma[2] = 0.5, sigma[3] = 0.03, sigma[5] = 0.01;
  sigma[11] = 0.04, sigma[12] = 0.05, sigma[13] = 0.06;
  const StageVector nominal = StageVectorOf(StageKinematics{});
  auto elevation_deg = [](const StageKinematics& s, double pan, double tilt) {
    return DegFromRad(std::asin(Forward(s, pan, tilt).z()));
  };
  for (const double tilt : {-17.0, 0.0}) {
    double sum2 = 0.0;
    int n = 0;
    for (double pan = 0.0; pan < 360.0; pan += 15.0, ++n)
      for (int k = 0; k < kStageParameterCount; ++k) {
        StageVector moved = nominal;
        moved[k] += sigma[k];
        const StageKinematics s = StageKinematicsOf(moved, StageKinematics{});
        sum2 +=
            std::pow(elevation_deg(s, pan, tilt) - elevation_deg(StageKinematics{}, pan, tilt), 2);
      }
    EXPECT_NEAR(std::sqrt(sum2 / n), SightTiltSigmaDeg(sigma), 1e-3 * SightTiltSigmaDeg(sigma))
        << tilt;
  }
}

TEST(StageKinematics, RigOffsetSweepsACircleUnderPan) {
  StageKinematics s;
  s.rig_offset_m = {0.0, 0.1, 0.2};
  for (double pan = 0; pan < 360; pan += 30) {
    const Eigen::Vector3d origin = s.LFromS(pan, 0).translation();
    EXPECT_NEAR(origin.z(), 0.2, 1e-12);
    EXPECT_NEAR(origin.head<2>().norm(), 0.1, 1e-12);
  }
  // Under tilt the offset turns about the tilt axis: Rx(t) (0, 0.1, 0.2).
  const Eigen::Vector3d tilted = s.LFromS(0, 30).translation();
  const double t = RadFromDeg(30);
  EXPECT_NEAR(tilted.y(), 0.1 * std::cos(t) - 0.2 * std::sin(t), 1e-12);
  EXPECT_NEAR(tilted.z(), 0.1 * std::sin(t) + 0.2 * std::cos(t), 1e-12);
}

TEST(StageKinematics, TiltAxisOffsetIsNotRotatedByTilt) {
  StageKinematics s;
  s.tilt_axis_offset_m = {0.0, 0.05, 0.12};
  EXPECT_TRUE(s.LFromS(0, 0).translation().isApprox(s.LFromS(0, 25).translation(), 1e-12));
  EXPECT_TRUE(s.LFromS(90, 0).translation().isApprox(Eigen::Vector3d(0.05, 0.0, 0.12), 1e-12));
}

TEST(StageKinematics, StationMarkIsBelowTheStageCentre) {
  StageKinematics s;
  s.height_above_mark_m = 1.42;
  EXPECT_TRUE(s.StationMarkInL().isApprox(Eigen::Vector3d(0, 0, -1.42)));
}

// The crew tapes the tilt axis above the mark. L's origin lies the tilt axis's height under
// it, so two descriptions of one stage that put the origin at different heights under the same
// tilt axis hang the mark at the same place below it.
TEST(StageKinematics, TheInstrumentHeightHangsTheMarkFromTheTiltAxis) {
  StageKinematics s;
  s.levelling_x_deg = 0.2;
  s.tilt_axis_offset_m = {0.0, 0.02, 0.12};
  s.rig_offset_m = {0.0, 0.0, 0.1};
  ASSERT_TRUE(s.SetInstrumentHeight(1.62));
  EXPECT_NEAR(s.height_above_mark_m, 1.50, 1e-12);
  EXPECT_NEAR(s.InstrumentHeightM(), 1.62, 1e-12);
  // A tape shorter than the tilt axis stands above the origin would put the mark above the
  // stage: refused.
  const Status low = StageKinematics(s).SetInstrumentHeight(0.11);
  ASSERT_FALSE(low);
  EXPECT_NE(low.error().find("0.11 m: below"), std::string::npos) << low.error();
  StageKinematics lower = s;  // the same stage, its origin 4 mm lower
  lower.tilt_axis_offset_m.z() += 0.004;
  ASSERT_TRUE(lower.SetInstrumentHeight(1.62));
  for (double pan : {0.0, 90.0, 200.0})
    for (double tilt : {-10.0, 15.0}) {
      const Eigen::Vector3d camera = s.LFromS(pan, tilt).translation();
      const Eigen::Vector3d same = lower.LFromS(pan, tilt).translation();
      EXPECT_NEAR((camera - s.StationMarkInL()).z(), (same - lower.StationMarkInL()).z(), 1e-5);
    }
}

TEST(StageKinematics, CheckRejectsNonsense) {
  std::string why;
  StageKinematics s;
  EXPECT_TRUE(s.Check(&why));
  s.levelling_x_deg = std::nan("");
  EXPECT_FALSE(s.Check(&why));
  s = StageKinematics();
  s.rig_offset_m = {0, 0, 3};
  EXPECT_FALSE(s.Check(&why));
  s = StageKinematics();
  s.height_above_mark_m = -1;
  EXPECT_FALSE(s.Check(&why));
}

TEST(Calibration, LeftCameraOfIdealRigLooksAlongPanDirection) {
  Calibration cal;
  cal.rig.baseline_m = 0.5;
  const Eigen::Isometry3d left = cal.LFromCamera(Side::kLeft, 90, 0);
  EXPECT_TRUE((left.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));
  // At pan 90 the baseline (left to right) points south: the left camera is north.
  EXPECT_TRUE(left.translation().isApprox(Eigen::Vector3d(0, 0.25, 0), 1e-12));
  const Eigen::Isometry3d right = cal.LFromCamera(Side::kRight, 90, 0);
  EXPECT_TRUE(right.translation().isApprox(Eigen::Vector3d(0, -0.25, 0), 1e-12));
}

}  // namespace
}  // namespace ts
