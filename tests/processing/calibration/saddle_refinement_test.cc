// The X-junction refinement on junctions drawn with a known centre: sharp, aliased edges at
// any angle between them (a board seen obliquely), noise, a start half a pixel off; and a dark
// square beside the junction (a ChArUco marker), which pulls the refinement off the centre
// unless its pixels are left out.
#include "processing/calibration/saddle_refinement.h"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace ts {
namespace {

constexpr int kSize = 64;

struct Junction {
  Eigen::Vector2d centre;
  Eigen::Vector2d a, b;  // unit directions of its two edges
};

// Image coordinates of a point in the junction's own frame (along a, along b).
Eigen::Vector2d JunctionCoordinates(const Junction& j, const Eigen::Vector2d& p) {
  Eigen::Matrix2d m;
  m.col(0) = j.a;
  m.col(1) = j.b;
  return m.inverse() * (p - j.centre);
}

// Bright and dark quadrants, 8 x 8 samples a pixel (the pixel's area, no optics: edges as
// sharp as a sensor gives them), a dark square ("marker") in one bright quadrant from `marker`
// to `marker` + 6 along both edges when marker > 0, noise of 2 DN.
cv::Mat Draw(const Junction& j, double marker, std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, 2.0);
  cv::Mat image(kSize, kSize, CV_8UC1);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      double sum = 0.0;
      for (int sy = 0; sy < 8; ++sy)
        for (int sx = 0; sx < 8; ++sx) {
          const Eigen::Vector2d p(x - 0.5 + (sx + 0.5) / 8.0, y - 0.5 + (sy + 0.5) / 8.0);
          const Eigen::Vector2d uv = JunctionCoordinates(j, p);
          bool bright = (uv.x() > 0) == (uv.y() > 0);
          if (marker > 0 && uv.x() > marker && uv.y() > marker && uv.x() < marker + 6 &&
              uv.y() < marker + 6)
            bright = false;
          sum += bright ? 200.0 : 30.0;
        }
      image.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(sum / 64.0 + noise(rng));
    }
  return image;
}

Junction RandomJunction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double first = 2 * M_PI * u(rng);
  const double between = (60.0 + 60.0 * u(rng)) * M_PI / 180.0;  // an oblique view's
  return {Eigen::Vector2d(kSize / 2 + 2 * u(rng) - 1, kSize / 2 + 2 * u(rng) - 1),
          Eigen::Vector2d(std::cos(first), std::sin(first)),
          Eigen::Vector2d(std::cos(first + between), std::sin(first + between))};
}

// RMS error over 40 junctions, refined from half a pixel off (by OpenCV's cornerSubPix on the
// image as it is when `opencv`).
double RmsError(double marker, bool leave_marker_out, double smoothing_px, bool opencv = false) {
  std::mt19937_64 rng(7);
  double sum = 0.0;
  constexpr int kJunctions = 40;
  for (int k = 0; k < kJunctions; ++k) {
    const Junction j = RandomJunction(rng);
    const cv::Mat image = Draw(j, marker, rng);
    std::vector<Eigen::Vector2d> corners{j.centre + Eigen::Vector2d(0.4, -0.35)};
    const SaddlePixelTest within_cross = [&](size_t, const Eigen::Vector2d& p) {
      const Eigen::Vector2d uv = JunctionCoordinates(j, p).cwiseAbs();
      return std::min(uv.x(), uv.y()) <= marker - (2 * smoothing_px + 1.5);
    };
    SaddleRefinementOptions options;
    options.smoothing_px = smoothing_px;
    if (opencv) {
      std::vector<cv::Point2f> p{cv::Point2f(corners[0].x(), corners[0].y())};
      cv::cornerSubPix(image, p, cv::Size(12, 12), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 50, 1e-4));
      sum += (Eigen::Vector2d(p[0].x, p[0].y) - j.centre).squaredNorm();
      continue;
    }
    std::vector<bool> refined;
    RefineSaddles(image, {12.0}, leave_marker_out ? within_cross : SaddlePixelTest{}, options,
                  &corners, &refined);
    EXPECT_TRUE(refined[0]) << k;
    sum += (corners[0] - j.centre).squaredNorm();
  }
  return std::sqrt(sum / kJunctions);
}

TEST(SaddleRefinement, FindsTheCentreOfSharpObliqueJunctionsToAFewHundredthsOfAPixel) {
  const double smoothed = RmsError(0.0, false, 1.0);
  const double raw = RmsError(0.0, false, 0.0);
  const double opencv = RmsError(0.0, false, 0.0, true);
  std::printf("RMS error: smoothed %.4f px, unsmoothed %.4f px, cornerSubPix %.4f px\n", smoothed,
              raw, opencv);
  EXPECT_LT(smoothed, 0.03);
  EXPECT_LT(smoothed, 0.7 * raw) << "smoothing spreads the aliased edges over pixels enough";
  EXPECT_LT(smoothed, 0.7 * opencv);
}

TEST(SaddleRefinement, AMarkerBesideTheJunctionIsLeftOut) {
  const double with_marker_out = RmsError(7.0, true, 1.0);
  const double with_marker_in = RmsError(7.0, false, 1.0);
  std::printf("RMS error: marker left out %.4f px, marker in the window %.4f px\n", with_marker_out,
              with_marker_in);
  EXPECT_LT(with_marker_out, 0.03);
  EXPECT_GT(with_marker_in, 3 * with_marker_out);
}

TEST(SaddleRefinement, AWindowWithOneStraightEdgeRefinesNothing) {
  cv::Mat image(kSize, kSize, CV_8UC1, cv::Scalar(30));
  image(cv::Rect(0, 0, kSize / 2, kSize)).setTo(200);
  std::vector<Eigen::Vector2d> corners{{kSize / 2.0, kSize / 2.0}};
  std::vector<bool> refined;
  RefineSaddles(image, {8.0}, {}, {}, &corners, &refined);
  EXPECT_FALSE(refined[0]);
  EXPECT_EQ(corners[0], Eigen::Vector2d(kSize / 2.0, kSize / 2.0)) << "left where it was";
}

}  // namespace
}  // namespace ts
