#include "processing/products/panorama.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "tests/common/paper_rig.h"

namespace ts {
namespace {

TEST(LargestViewTurn, IsTheRotationTheStageAddsToEveryView) {
  const Calibration from = testing::PaperCalibration();
  const std::vector<StereoPairImages> poses = {
      {0, 0.0, 0.0, {}, {}}, {1, 90.0, 0.0, {}, {}}, {2, 210.0, 32.0, {}, {}}};
  EXPECT_NEAR(LargestViewTurnDeg(from, from, poses), 0.0, 1e-9);
  Calibration levelled = from;
  levelled.stage.levelling_x_deg = 0.05;  // turns the whole stage: every view alike
  EXPECT_NEAR(LargestViewTurnDeg(from, levelled, poses), 0.05, 1e-9);
  Calibration bumped = from;
  bumped.stage.tilt_zero_deg = 0.3;  // a turn about the tilt axis, whatever the pan
  EXPECT_NEAR(LargestViewTurnDeg(from, bumped, poses), 0.3, 1e-9);
  Calibration moved = from;
  moved.stage.rig_offset_m.z() = 0.02;  // the cameras move, their views do not turn
  EXPECT_NEAR(LargestViewTurnDeg(from, moved, poses), 0.0, 1e-9);
}

// The turn is how far the panorama moves: drawn on a stage whose pan zero differs by 1 deg, the
// view stands 1 deg (5 pixels at 0.2 deg) along, as phase correlation of the two finds.
TEST(LargestViewTurn, IsHowFarThePanoramaMoves) {
  const Calibration from = testing::PaperCalibration();
  cv::Mat texture(1040, 1392, CV_8U);
  std::mt19937 random(7);
  std::uniform_int_distribution<int> grey(0, 255);
  for (int r = 0; r < texture.rows; ++r)
    for (int c = 0; c < texture.cols; ++c) texture.at<uint8_t>(r, c) = grey(random);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 12.0);  // detail at the panorama's pixel
  cv::normalize(texture, texture, 0, 255, cv::NORM_MINMAX);
  const std::vector<StereoPairImages> pair = {{0, 180.0, 0.0, texture, cv::Mat()}};
  Calibration turned = from;
  turned.stage.pan_zero_deg = 1.0;
  const PanoramaOptions o;
  const double turn_px = LargestViewTurnDeg(from, turned, pair) / o.deg_per_px;
  EXPECT_NEAR(turn_px, 5.0, 1e-6);
  cv::Mat a, b;
  RenderPanorama(from, pair, o).convertTo(a, CV_64F);
  RenderPanorama(turned, pair, o).convertTo(b, CV_64F);
  ASSERT_EQ(a.size(), b.size());  // a turn about the pan axis keeps the rows seen
  const cv::Point2d shift = cv::phaseCorrelate(a, b);
  EXPECT_NEAR(std::abs(shift.x), turn_px, 0.3);
  EXPECT_NEAR(shift.y, 0.0, 0.3);
}

}  // namespace
}  // namespace ts
