#include "processing/cloud/height_blunder_filter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace ts {
namespace {

TEST(HeightBlunderFilter, FindsSpikesAndPitsOnASlopeAndNothingElse) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 30.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::uniform_real_distribution<double> offset(2.0, 4.0);  // mismatches scatter in depth
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> truth;
  for (int i = 0; i < 30000; ++i) {
    const double x = u(rng), y = u(rng);
    double z = 0.2 * x + noise(rng);  // 20 % slope: 0.25 m over half a window
    const bool blunder = i % 100 == 0;
    if (blunder) z += (i % 200 == 0 ? 1.0 : -1.0) * offset(rng);
    points.emplace_back(x, y, z);
    truth.push_back(blunder);
  }
  HeightBlunderOptions one_surface;
  one_surface.min_layer_points = 0;
  for (const HeightBlunderOptions& o : {HeightBlunderOptions{}, one_surface}) {
    const std::vector<uint8_t> found = FindHeightBlunders(points, o);
    ASSERT_EQ(found.size(), points.size());
    EXPECT_EQ(found, truth) << "min_layer_points " << o.min_layer_points;
  }
}

TEST(HeightBlunderFilter, KeepsPointsWithTooFewNeighbours) {
  const std::vector<Eigen::Vector3d> points = {{0, 0, 0}, {0.1, 0, 50}, {100, 100, 3}};
  const std::vector<uint8_t> found = FindHeightBlunders(points, HeightBlunderOptions{});
  EXPECT_EQ(found, (std::vector<uint8_t>{0, 0, 0}));
}

// The edge of a grove: in a window mostly of canopy (4 m up), the ground seen beneath it is
// a second layer, not blunders; a lone point in neither layer is still one.
TEST(HeightBlunderFilter, KeepsASecondLayerAndStillFindsALonePoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 60; ++i) points.emplace_back(u(rng), u(rng), 4.0 + 0.3 * noise(rng));
  for (int i = 0; i < 8; ++i) points.emplace_back(u(rng), u(rng), noise(rng));  // ground
  points.emplace_back(1.0, 1.0, -2.0);                                          // a pit
  HeightBlunderOptions layers;
  const std::vector<uint8_t> found = FindHeightBlunders(points, layers);
  const std::vector<uint8_t> ground(found.begin() + 60, found.begin() + 68);
  EXPECT_EQ(ground, std::vector<uint8_t>(8, 0));
  EXPECT_EQ(found.back(), 1);
  EXPECT_EQ(std::count(found.begin(), found.begin() + 60, 1), 0);

  HeightBlunderOptions one_surface = layers;  // seed 003's filter as it was
  one_surface.min_layer_points = 0;
  const std::vector<uint8_t> old = FindHeightBlunders(points, one_surface);
  EXPECT_EQ(std::vector<uint8_t>(old.begin() + 60, old.begin() + 68), std::vector<uint8_t>(8, 1));
  EXPECT_EQ(old.back(), 1);
}

TEST(HeightBlunderFilter, RejectsBadOptions) {
  HeightBlunderOptions o;
  o.threshold_m = -1.0;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("threshold_m"), std::string::npos);
  EXPECT_THROW(FindHeightBlunders({}, o), std::invalid_argument);
  HeightBlunderOptions layer;
  layer.layer_tolerance_m = 0.0;
  EXPECT_FALSE(layer.Check(&why));
  EXPECT_NE(why.find("layer_tolerance_m"), std::string::npos);
}

}  // namespace
}  // namespace ts
