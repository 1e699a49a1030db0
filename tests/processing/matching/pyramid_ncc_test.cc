// NCC on a pyramid against known disparity fields: a synthetic texture seen under a slanted
// plane's disparity (as near ground is), and single windows with an exact shift.
#include "processing/matching/pyramid_ncc.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "tests/common/random_texture.h"

namespace ts {
namespace {

using testing::RandomTexture;

// right(x, y) = left(x + d(y), y) with d = 20 + 0.25 y: left (x, y) <-> right (x - d, y).
double TrueDisparity(int y) { return 20.0 + 0.25 * y; }

cv::Mat RightView(const cv::Mat& left) {
  cv::Mat map_x(left.size(), CV_32FC1), map_y(left.size(), CV_32FC1);
  for (int y = 0; y < left.rows; ++y)
    for (int x = 0; x < left.cols; ++x) {
      map_x.at<float>(y, x) = static_cast<float>(x + TrueDisparity(y));
      map_y.at<float>(y, x) = static_cast<float>(y);
    }
  cv::Mat right;
  cv::remap(left, right, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return right;
}

// The slant (0.25 px per row, as ground 5 m away) spreads an integer NCC estimate by about
// +-1.5 px; what counts is that it stays within least-squares matching's pull-in range.
TEST(PyramidNcc, FollowsASlantedDisparityFieldThroughTheLevelsToTheTopAndBottomRows) {
  const cv::Mat left = RandomTexture(320, 240, 5), right = RightView(left);
  for (const int finest : {0, 1}) {
    const DisparityMap map = MatchPyramid(left, right, 0, 120, finest, {});
    EXPECT_EQ(map.level, finest);
    EXPECT_GE(map.disparity.cols, left.cols >> finest);
    int good = 0, total = 0;
    // Every row and the last columns too (their windows take the border pixels again); on
    // the left, only where the right image shows the point (x >= d).
    for (int y = 0; y < map.disparity.rows; ++y)
      for (int x = (90 >> finest); x < map.disparity.cols; ++x) {
        ++total;
        const double truth = TrueDisparity(y << finest) / (1 << finest);
        good += std::abs(map.disparity.at<int16_t>(y, x) - truth) <= 2.0;
      }
    EXPECT_GT(good, 0.97 * total) << "finest level " << finest;
  }
}

TEST(PyramidNcc, BestDisparityAtFindsAnExactShiftBothWays) {
  const cv::Mat left = RandomTexture(200, 100, 6);
  cv::Mat right = cv::Mat::zeros(left.size(), CV_32FC1);
  left.colRange(17, 200).copyTo(right.colRange(0, 183));  // d = 17 everywhere
  double score = 0.0;
  // (Sums in single precision: a perfect match scores 1 to about 1e-5.)
  EXPECT_EQ(BestDisparityAt(left, right, 120, 50, 0, 60, 3, +1, &score), 17);
  EXPECT_NEAR(score, 1.0, 2e-5);
  EXPECT_EQ(BestDisparityAt(right, left, 80, 50, 0, 60, 3, -1, &score), 17);
  EXPECT_NEAR(score, 1.0, 2e-5);
  // A range that excludes the truth finds something else, with a poor score.
  EXPECT_NE(BestDisparityAt(left, right, 120, 50, 30, 60, 3, +1, &score), 17);
  EXPECT_LT(score, 0.7);
  // Windows that do not fit give none.
  EXPECT_EQ(BestDisparityAt(left, right, 2, 50, 0, 60, 3, +1, &score), -1);
  EXPECT_EQ(BestDisparityAt(left, right, 10, 50, 20, 60, 3, +1, &score), -1);
}

// The textbook NCC of two windows, in double precision.
double DirectNcc(const cv::Mat& a, const cv::Mat& b, int ua, int ub, int v, int h) {
  const cv::Rect wa(ua - h, v - h, 2 * h + 1, 2 * h + 1), wb(ub - h, v - h, 2 * h + 1, 2 * h + 1);
  cv::Mat x, y;
  a(wa).convertTo(x, CV_64F);
  b(wb).convertTo(y, CV_64F);
  x -= cv::mean(x)[0];
  y -= cv::mean(y)[0];
  return x.dot(y) / std::sqrt(x.dot(x) * y.dot(y));
}

TEST(PyramidNcc, BestDisparityAtAgreesWithTheTextbookNccEverywhere) {
  // Every window size, both directions, and candidates up to the images' right edge (where
  // the padded rows of the fast sums would leave the image). The sums are in single
  // precision: scores agree to 1e-4, winners exactly.
  const cv::Mat left = RandomTexture(120, 40, 8), right = RandomTexture(120, 40, 9);
  int compared = 0;
  for (int h = 1; h <= 6; ++h)
    for (const int sign : {+1, -1})
      for (int u = h; u < left.cols - h; u += 3) {
        const int v = 20, lo = 0, hi = 12;
        double score = 0.0;
        const int found = BestDisparityAt(left, right, u, v, lo, hi, h, sign, &score);
        int best = -1;
        double best_score = -2.0;
        for (int d = lo; d <= hi; ++d) {
          const int c = u - sign * d;
          if (c - h < 0 || c + h >= right.cols) continue;
          const double ncc = DirectNcc(left, right, u, c, v, h);
          if (ncc > best_score) best_score = ncc, best = d;
        }
        ASSERT_EQ(found, best) << "h " << h << " sign " << sign << " u " << u;
        if (best < 0) continue;
        EXPECT_NEAR(score, best_score, 1e-4) << "h " << h << " sign " << sign << " u " << u;
        ++compared;
      }
  EXPECT_GT(compared, 400);
}

TEST(PyramidNcc, RejectsBadOptions) {
  PyramidNccOptions o;
  std::string why;
  o.refine_radius_px = 0;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("refine_radius_px"), std::string::npos);
}

}  // namespace
}  // namespace ts
