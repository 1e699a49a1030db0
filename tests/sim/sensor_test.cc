#include "sim/sensor.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ts::sim {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics c;
  c.width_px = 200;
  c.height_px = 150;
  c.principal_distance_px = 180;
  c.principal_point_x_px = 99.5;
  c.principal_point_y_px = 74.5;
  return c;
}

double MeanOf(const cv::Mat& m, cv::Rect r) { return cv::mean(m(r))[0]; }

TEST(Sensor, SignalIsLinearInExposureAndRadiance) {
  SensorModel s;
  s.noise = false;
  s.vignetting_strength = 0.0;
  const cv::Mat radiance(150, 200, CV_32FC1, cv::Scalar(0.25));
  const cv::Mat a = ExposeImage(radiance, Camera(), s, 4000, 0, PixelFormat::kMono16, 1);
  const cv::Mat b = ExposeImage(radiance, Camera(), s, 8000, 0, PixelFormat::kMono16, 1);
  const double black = s.black_level_fraction * 65535;
  const double expected = 0.25 * s.electrons_per_us * 4000 / s.full_well_e * 65535;
  EXPECT_NEAR(MeanOf(a, {0, 0, 200, 150}) - black, expected, 1.0);
  EXPECT_NEAR(MeanOf(b, {0, 0, 200, 150}) - black, 2 * expected, 1.0);
  // 6 dB doubles the signal.
  const cv::Mat g = ExposeImage(radiance, Camera(), s, 4000, 6.0206, PixelFormat::kMono16, 1);
  EXPECT_NEAR(MeanOf(g, {0, 0, 200, 150}) - black, 2 * expected, 2.0);
}

TEST(Sensor, ClipsAtFullScaleAndRightCameraIsDarker) {
  SensorModel left, right;
  left.noise = right.noise = false;
  right.sensitivity = 0.92;
  const cv::Mat radiance(150, 200, CV_32FC1, cv::Scalar(0.3));
  const cv::Mat l = ExposeImage(radiance, Camera(), left, 8000, 0, PixelFormat::kMono8, 1);
  const cv::Mat r = ExposeImage(radiance, Camera(), right, 8000, 0, PixelFormat::kMono8, 1);
  EXPECT_LT(MeanOf(r, {90, 65, 20, 20}), MeanOf(l, {90, 65, 20, 20}));
  const cv::Mat bright(150, 200, CV_32FC1, cv::Scalar(10.0));
  double max_value;
  cv::minMaxLoc(ExposeImage(bright, Camera(), left, 8000, 0, PixelFormat::kMono8, 1), nullptr,
                &max_value);
  EXPECT_EQ(max_value, 255.0);
}

TEST(Sensor, VignettingFollowsTheCosineFourthLaw) {
  SensorModel s;
  s.noise = false;
  s.black_level_fraction = 0.0;
  const cv::Mat radiance(150, 200, CV_32FC1, cv::Scalar(0.3));
  const cv::Mat m = ExposeImage(radiance, Camera(), s, 8000, 0, PixelFormat::kMono16, 1);
  const double dx = (0 - 99.5) / 180.0, dy = (0 - 74.5) / 180.0;
  const double cos2 = 1.0 / (1.0 + dx * dx + dy * dy);
  EXPECT_NEAR(m.at<uint16_t>(0, 0) / static_cast<double>(m.at<uint16_t>(75, 100)), cos2 * cos2,
              0.002);
}

TEST(Sensor, NoiseHasTheShotAndReadNoiseStandardDeviation) {
  SensorModel s;
  s.vignetting_strength = 0.0;
  const cv::Mat radiance(150, 200, CV_32FC1, cv::Scalar(0.2));
  const cv::Mat m = ExposeImage(radiance, Camera(), s, 5000, 0, PixelFormat::kMono16, 9);
  cv::Scalar mean, stddev;
  cv::meanStdDev(m, mean, stddev);
  const double electrons = 0.2 * s.electrons_per_us * 5000;
  const double dn_per_e = 65535 / s.full_well_e;
  const double expected = std::sqrt(electrons + s.read_noise_e * s.read_noise_e) * dn_per_e;
  EXPECT_NEAR(stddev[0], expected, 0.05 * expected);
  // Reproducible for a seed, different for another.
  EXPECT_EQ(cv::norm(m, ExposeImage(radiance, Camera(), s, 5000, 0, PixelFormat::kMono16, 9),
                     cv::NORM_INF),
            0.0);
  EXPECT_GT(cv::norm(m, ExposeImage(radiance, Camera(), s, 5000, 0, PixelFormat::kMono16, 10),
                     cv::NORM_INF),
            0.0);
}

}  // namespace
}  // namespace ts::sim
