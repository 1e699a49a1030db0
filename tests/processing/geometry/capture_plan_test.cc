#include "processing/geometry/capture_plan.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "processing/geometry/camera_model.h"
#include "tests/common/paper_rig.h"

namespace ts {
namespace {

Calibration PaperRig() { return testing::PaperCalibration(1.5); }

TEST(CapturePlan, TwelveAzimuthsThirtyDegreesApartAtOneTilt) {
  const auto plan = MakeCapturePlan(PaperRig(), {});
  ASSERT_EQ(plan.size(), 12u);
  for (size_t i = 0; i < plan.size(); ++i) {
    EXPECT_DOUBLE_EQ(plan[i].pan_deg, 30.0 * i);
    EXPECT_DOUBLE_EQ(plan[i].tilt_deg, plan[0].tilt_deg);
  }
  // Neighbours overlap: the horizontal field of view exceeds the 30 deg step.
  const double hfov = 2 * std::atan(696.0 / (12.0e3 / 6.45)) * 180 / M_PI;
  EXPECT_GT(hfov, 30.0 + 5.0);
}

TEST(CapturePlan, AutomaticTiltSeesTheGroundFromAFewMetresToTheSquareCorners) {
  const Calibration cal = PaperRig();
  const double tilt = AutomaticTiltDeg(cal, {});
  EXPECT_LT(tilt, -10.0);
  EXPECT_GT(tilt, -25.0);
  // Flat ground at -1.5 m, straight ahead at 42.5 m: in the image, 5 deg below the top edge.
  const CameraModel camera(cal.rig.left);
  const Eigen::Isometry3d pose = cal.LFromCamera(Side::kLeft, 0.0, tilt);
  Eigen::Vector2d far, near;
  ASSERT_TRUE(camera.Project(pose.inverse() * Eigen::Vector3d(-0.25, 42.5, -1.5), &far));
  EXPECT_GT(far.y(), 130.0);  // the 5 deg margin is about 160 px
  EXPECT_LT(far.y(), 190.0);
  const double nearest = NearestGroundRangeM(cal, tilt);
  EXPECT_GT(nearest, 2.0);
  EXPECT_LT(nearest, 3.5);
  ASSERT_TRUE(camera.Project(pose.inverse() * Eigen::Vector3d(-0.25, nearest + 0.1, -1.5), &near));
  EXPECT_LT(near.y(), 1040.0);
}

TEST(CapturePlan, RowsAndLimits) {
  CapturePlanOptions o;
  o.azimuths = 8;
  o.tilts_deg = {-25.0, -5.0};
  o.first_pan_deg = -10.0;
  const auto plan = MakeCapturePlan(PaperRig(), o);
  ASSERT_EQ(plan.size(), 16u);
  EXPECT_DOUBLE_EQ(plan[0].pan_deg, 350.0);
  EXPECT_DOUBLE_EQ(plan[9].tilt_deg, -5.0);
  o.tilts_deg = {-40.0};
  EXPECT_THROW(MakeCapturePlan(PaperRig(), o), std::invalid_argument);
  o = {};
  o.azimuths = 0;
  EXPECT_THROW(MakeCapturePlan(PaperRig(), o), std::invalid_argument);
}

TEST(CapturePlan, UpperPoseOverlapsTheViewBelowAndStopsAtTheStageLimit) {
  const Calibration cal = PaperRig();
  const StagePose below{120.0, AutomaticTiltDeg(cal, {})};
  StagePose upper;
  ASSERT_TRUE(UpperPose(cal, below, {}, &upper));
  EXPECT_DOUBLE_EQ(upper.pan_deg, 120.0);
  // The paper's rig sees 31.1 deg vertically (1040 px at 12 mm, 6.45 um): the bottom edge of
  // the upper view is 6 deg below the top edge of the view below.
  const double field = 2 * std::atan(520.0 / (12.0e3 / 6.45)) * 180 / M_PI;
  EXPECT_NEAR(upper.tilt_deg - below.tilt_deg, field - 6.0, 0.05);
  // From there the next one would pass the 32 deg limit by 5.5 deg: it is clamped; from the
  // limit there is nothing above.
  StagePose top;
  ASSERT_TRUE(UpperPose(cal, upper, {}, &top));
  EXPECT_DOUBLE_EQ(top.tilt_deg, 32.0);
  EXPECT_FALSE(UpperPose(cal, top, {}, &top));
  CapturePlanOptions o;
  o.row_overlap_deg = 25.0;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("row_overlap_deg"), std::string::npos);
}

}  // namespace
}  // namespace ts
