#include "processing/dem/kriging.h"

#include <gtest/gtest.h>

#include <random>

namespace ts {
namespace {

VariogramModel Linearish() {  // spherical, 2 m^2 sill, 50 m range: gamma(h) nearly linear
  VariogramModel m;
  m.kind = VariogramKind::kSpherical;
  m.nugget = 0.0;
  m.partial_sill = 2.0;
  m.range_m = 50.0;
  return m;
}

Raster OneCell(double x, double y) { return Raster::Make(x - 0.5, y + 0.5, 1.0, 1, 1); }

// One point at distance d: lambda = 1, mu = gamma(d), sigma^2 = 2 gamma(d).
TEST(Kriging, OnePointGivesItsHeightAndTwiceTheSemivariance) {
  const VariogramModel m = Linearish();
  Raster dem = OneCell(0, 0), std_dev;
  KrigingOptions o;
  KrigeOnto({{1.5, 2.0, 7.25}}, m, o, &dem, &std_dev);
  EXPECT_NEAR(dem.at(0, 0), 7.25, 1e-5);
  EXPECT_NEAR(std_dev.at(0, 0), std::sqrt(2.0 * m(2.5)), 1e-5);
}

// Two points symmetric about the cell centre: lambda = 1/2 each, mu = gamma(d) - gamma(2d)/2,
// sigma^2 = 2 gamma(d) - gamma(2d) / 2.
TEST(Kriging, TwoSymmetricPointsAreAveragedWithTheKnownVariance) {
  const VariogramModel m = Linearish();
  Raster dem = OneCell(10, 20), std_dev;
  KrigeOnto({{8, 20, 1.0}, {12, 20, 3.0}}, m, KrigingOptions{}, &dem, &std_dev);
  EXPECT_NEAR(dem.at(0, 0), 2.0, 1e-5);
  EXPECT_NEAR(std_dev.at(0, 0), std::sqrt(2.0 * m(2.0) - 0.5 * m(4.0)), 1e-5);
}

// An exact interpolator: at a data point the estimate is the datum and the variance is zero
// (no nugget); a plane sampled all around is reproduced.
TEST(Kriging, HonoursDataAndReproducesAPlane) {
  std::vector<Eigen::Vector3d> points;
  for (double x = -10; x <= 10; x += 1.0)
    for (double y = -10; y <= 10; y += 1.0) points.emplace_back(x, y, 100 + 0.3 * x - 0.2 * y);
  Raster dem = Raster::Make(-5, 5, 1.0, 10, 10), std_dev;
  KrigeOnto(points, Linearish(), KrigingOptions{}, &dem, &std_dev);
  for (int r = 0; r < 10; ++r)
    for (int c = 0; c < 10; ++c)
      EXPECT_NEAR(dem.at(r, c), 100 + 0.3 * dem.CellCentreX(c) - 0.2 * dem.CellCentreY(r), 1e-3);
  Raster at_point = OneCell(3, 4), s;
  KrigeOnto(points, Linearish(), KrigingOptions{}, &at_point, &s);
  EXPECT_NEAR(at_point.at(0, 0), 100 + 0.9 - 0.8, 1e-4);
  EXPECT_NEAR(s.at(0, 0), 0.0, 2e-3);
}

// Points on one side only of a cell on a 30 % slope (the far side of a gap): the linear drift
// carries the slope into the gap, ordinary kriging levels towards the neighbours' mean; the
// kriging std with drift grows as the cell gets farther from the data.
TEST(Kriging, LinearDriftBridgesAGapOnASlope) {
  std::vector<Eigen::Vector3d> points;
  for (double x = -10; x <= 0; x += 0.5)
    for (double y = -5; y <= 5; y += 0.5) points.emplace_back(x, y, 0.3 * x);
  KrigingOptions o;
  o.max_distance_m = 10.0;
  Raster dem = Raster::Make(0.0, 0.5, 1.0, 4, 1), s;  // cells at x = 0.5, 1.5, 2.5, 3.5
  KrigeOnto(points, Linearish(), o, &dem, &s);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(dem.at(0, c), 0.3 * dem.CellCentreX(c), 1e-3) << c;
  for (int c = 1; c < 4; ++c) EXPECT_GT(s.at(0, c), s.at(0, c - 1));
  o.linear_drift = false;
  KrigeOnto(points, Linearish(), o, &dem, &s);
  EXPECT_LT(dem.at(0, 3), 0.3 * 3.5 - 0.5);
}

TEST(Kriging, CellsFarFromEveryPointAreNodata) {
  Raster dem = Raster::Make(0, 10, 1.0, 10, 1), std_dev;
  KrigingOptions o;
  o.max_distance_m = 3.0;
  KrigeOnto({{0.5, 9.5, 1.0}}, Linearish(), o, &dem, &std_dev);
  EXPECT_FALSE(Raster::IsNoData(dem.at(0, 0)));
  EXPECT_FALSE(Raster::IsNoData(dem.at(0, 3)));  // 3.0 m away
  EXPECT_TRUE(Raster::IsNoData(dem.at(0, 4)));   // 4.0 m away
  EXPECT_TRUE(Raster::IsNoData(std_dev.at(0, 9)));
}

// A noisy, dense sampled surface: the thinned, fitted kriging is close to the truth and its
// standard deviation is of the size of its true error.
TEST(Kriging, FittedKrigingOfANoisySurfaceIsAccurateAndHonest) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-30, 30);
  std::normal_distribution<double> noise(0.0, 0.05);
  auto terrain = [](double x, double y) { return 2.0 * std::sin(x / 9.0) + 0.05 * x * y / 10; };
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 60000; ++i) {
    const double x = u(rng), y = u(rng);
    points.emplace_back(x, y, terrain(x, y) + noise(rng));
  }
  const KrigingResult k = KrigeDem(points, Raster::Make(-25, 25, 1.0, 50, 50), KrigingOptions{});
  double sum2 = 0, sum_var = 0;
  int n = 0;
  for (int r = 0; r < 50; ++r)
    for (int c = 0; c < 50; ++c) {
      ASSERT_FALSE(Raster::IsNoData(k.dem.at(r, c)));
      const double e = k.dem.at(r, c) - terrain(k.dem.CellCentreX(c), k.dem.CellCentreY(r));
      sum2 += e * e, sum_var += k.std.at(r, c) * k.std.at(r, c), ++n;
    }
  const double rmse = std::sqrt(sum2 / n), predicted = std::sqrt(sum_var / n);
  EXPECT_LT(rmse, 0.03);
  EXPECT_GT(predicted, 0.3 * rmse);
  EXPECT_LT(predicted, 3.0 * rmse);
  EXPECT_LT(k.points_used, points.size());
}

TEST(Kriging, RejectsBadOptions) {
  KrigingOptions o;
  o.neighbours = 0;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("neighbours"), std::string::npos);
  Raster dem = OneCell(0, 0), s;
  EXPECT_THROW(KrigeOnto({}, Linearish(), o, &dem, &s), std::invalid_argument);
}

}  // namespace
}  // namespace ts
