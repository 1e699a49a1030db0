#include "processing/cloud/fill_holes.h"

#include <gtest/gtest.h>

namespace ts {
namespace {

// A plane sampled at 1 cell in 25 (as an airborne cloud on a 1 m grid) is filled back to the
// plane (within the log-shaped dimples a membrane makes at each sample), and the known cells
// keep their values exactly.
TEST(FillHoles, RestoresAPlaneFromSparseSamples) {
  cv::Mat surface(60, 80, CV_32FC1, cv::Scalar(0)), known(60, 80, CV_8UC1, cv::Scalar(0));
  auto plane = [](int r, int c) { return 300.0f + 0.2f * c - 0.1f * r; };
  for (int r = 1; r < 60; r += 5)
    for (int c = 2; c < 80; c += 5)
      surface.at<float>(r, c) = plane(r, c), known.at<uint8_t>(r, c) = 1;
  const cv::Mat filled = FillHoles(surface, known, 400);
  double worst = 0.0;  // away from the grid's edge, where the membrane flattens
  for (int r = 10; r < 50; ++r)
    for (int c = 10; c < 70; ++c)
      worst = std::max(worst, std::abs(filled.at<float>(r, c) - plane(r, c)) + 0.0);
  EXPECT_LT(worst, 0.05);
  EXPECT_EQ(filled.at<float>(6, 7), plane(6, 7));
}

TEST(FillHoles, OneKnownCellFillsEverything) {
  cv::Mat surface(9, 9, CV_32FC1, cv::Scalar(0)), known(9, 9, CV_8UC1, cv::Scalar(0));
  surface.at<float>(4, 4) = 7.5f;
  known.at<uint8_t>(4, 4) = 1;
  const cv::Mat filled = FillHoles(surface, known);
  EXPECT_LT(cv::norm(filled - 7.5f, cv::NORM_INF), 1e-4);
}

TEST(FillHoles, NothingKnownGivesZeros) {
  cv::Mat surface(4, 4, CV_32FC1, cv::Scalar(3)), known(4, 4, CV_8UC1, cv::Scalar(0));
  EXPECT_EQ(cv::countNonZero(FillHoles(surface, known)), 0);
}

}  // namespace
}  // namespace ts
