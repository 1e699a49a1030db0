#include "processing/cloud/height_blunder_filter.h"

#include <gtest/gtest.h>

#include <random>

namespace ts {
namespace {

TEST(HeightBlunderFilter, FindsSpikesAndPitsOnASlopeAndNothingElse) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 30.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> truth;
  for (int i = 0; i < 30000; ++i) {
    const double x = u(rng), y = u(rng);
    double z = 0.2 * x + noise(rng);  // 20 % slope: 0.25 m over half a window
    const bool blunder = i % 100 == 0;
    if (blunder) z += (i % 200 == 0 ? 3.0 : -2.5);
    points.emplace_back(x, y, z);
    truth.push_back(blunder);
  }
  const std::vector<uint8_t> found = FindHeightBlunders(points, HeightBlunderOptions{});
  ASSERT_EQ(found.size(), points.size());
  EXPECT_EQ(found, truth);
}

TEST(HeightBlunderFilter, KeepsPointsWithTooFewNeighbours) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {0.1, 0, 50}, {100, 100, 3}};
  const std::vector<uint8_t> found = FindHeightBlunders(points, HeightBlunderOptions{});
  EXPECT_EQ(found, (std::vector<uint8_t>{0, 0, 0}));
}

TEST(HeightBlunderFilter, RejectsBadOptions) {
  HeightBlunderOptions o;
  o.threshold_m = -1.0;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("threshold_m"), std::string::npos);
  EXPECT_THROW(FindHeightBlunders({}, o), std::invalid_argument);
}

}  // namespace
}  // namespace ts
