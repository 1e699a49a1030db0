#include "acquisition/exposure_control.h"

#include <gtest/gtest.h>

namespace ts {
namespace {

cv::Mat Uniform(double fraction, int type = CV_8UC1) {
  const double full = type == CV_16UC1 ? 65535 : 255;
  return cv::Mat(300, 400, type, cv::Scalar(fraction * full));
}

TEST(ExposureControl, AcceptsAWellExposedPair) {
  const ExposureVerdict v = JudgeExposure(Uniform(0.35), Uniform(0.33), 4000, {});
  EXPECT_TRUE(v.ok);
  EXPECT_NEAR(v.mean, 0.34, 0.005);
  EXPECT_DOUBLE_EQ(v.next_exposure_us, 4000);
}

TEST(ExposureControl, DarkPairIsRetakenWithAProportionalExposure) {
  const ExposureVerdict v = JudgeExposure(Uniform(0.07), Uniform(0.07), 2000, {});
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.reason, "too dark");
  const double mean = 18.0 / 255.0;  // 0.07 of full scale, as an 8-bit value
  EXPECT_NEAR(v.mean, mean, 1e-9);
  EXPECT_NEAR(v.next_exposure_us, 2000 * 0.35 / mean, 1e-6);
}

TEST(ExposureControl, ClippedGroundIsRetakenDarkerButASkyIsNot) {
  cv::Mat sky_and_ground = Uniform(0.35);
  sky_and_ground.rowRange(0, 90).setTo(255);  // saturated sky in the top third only
  EXPECT_TRUE(JudgeExposure(sky_and_ground, sky_and_ground, 4000, {}).ok);
  cv::Mat clipped = Uniform(0.35, CV_16UC1);
  clipped.rowRange(150, 200).setTo(65535);  // saturated ground
  const ExposureVerdict v = JudgeExposure(clipped, clipped, 4000, {});
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.reason, "clipped");
  EXPECT_LE(v.next_exposure_us, 2000);
}

TEST(ExposureControl, AtTheExposureLimitTheBestPossibleIsAccepted) {
  ExposureOptions o;
  o.max_exposure_us = 10000;
  const ExposureVerdict v = JudgeExposure(Uniform(0.02), Uniform(0.02), 10000, o);
  EXPECT_TRUE(v.ok);  // nothing brighter is possible: no endless retakes
}

}  // namespace
}  // namespace ts
