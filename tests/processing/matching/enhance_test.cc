#include "processing/matching/enhance.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ts {
namespace {

cv::Mat Texture(unsigned seed) {
  cv::Mat m(120, 160, CV_32FC1);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 30, 200);
  cv::GaussianBlur(m, m, {0, 0}, 1.5);
  return m;
}

TEST(Enhance, WallisRemovesALinearExposureDifference) {
  const cv::Mat left = Texture(1);
  const cv::Mat right = 0.7 * left + 20.0;  // darker, less contrast, offset
  EnhanceOptions o;
  o.gaussian_sigma_px = 0.0;
  o.contrast = 1.0;
  o.brightness = 1.0;
  const cv::Mat a = Enhance(left, o), b = Enhance(right, o);
  const cv::Rect interior(20, 20, 120, 80);
  EXPECT_LT(cv::norm(a(interior), b(interior), cv::NORM_INF), 0.05);
  EXPECT_GT(cv::norm(left(interior), right(interior), cv::NORM_INF), 10.0);
}

TEST(Enhance, WallisReachesTheTargetStatistics) {
  EnhanceOptions o;
  o.gaussian_sigma_px = 0.0;
  o.contrast = 1.0;
  o.target_mean = 100.0;
  o.target_deviation = 40.0;
  const cv::Mat out = Enhance(0.2 * Texture(2) + 50.0, o);  // dull input
  cv::Scalar mean, deviation;
  cv::meanStdDev(out(cv::Rect(20, 20, 120, 80)), mean, deviation);
  EXPECT_NEAR(mean[0], 100.0, 2.0);
  EXPECT_NEAR(deviation[0], 40.0, 4.0);
}

TEST(Enhance, FlatAreasStayFlatAndGaussianReducesNoise) {
  const cv::Mat flat(60, 60, CV_8UC1, cv::Scalar(77));
  double lo, hi;
  cv::minMaxLoc(Enhance(flat, {}), &lo, &hi);
  EXPECT_NEAR(hi - lo, 0.0, 1e-3);
  // White noise of variance v through a Gaussian of sigma s keeps v / (4 pi s^2).
  cv::Mat noise(200, 200, CV_32FC1);
  cv::RNG(4).fill(noise, cv::RNG::NORMAL, 0.0, 10.0);
  EnhanceOptions o;
  o.wallis = false;
  o.gaussian_sigma_px = 2.0;
  cv::Scalar mean, deviation;
  cv::meanStdDev(Enhance(noise, o)(cv::Rect(20, 20, 160, 160)), mean, deviation);
  EXPECT_NEAR(deviation[0], 10.0 / std::sqrt(4 * M_PI * 4.0), 0.3);
}

TEST(Enhance, RejectsBadOptions) {
  EnhanceOptions o;
  o.wallis_window_px = 30;
  EXPECT_THROW(Enhance(Texture(1), o), std::invalid_argument);
  o = {};
  o.contrast = 2.0;
  EXPECT_THROW(Enhance(Texture(1), o), std::invalid_argument);
}

}  // namespace
}  // namespace ts
