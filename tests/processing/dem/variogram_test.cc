#include "processing/dem/variogram.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ts {
namespace {

// z = x along a line: every pair at distance h has gamma = h^2 / 2.
TEST(Variogram, ExperimentalOfALinearRampIsHalfTheSquaredLag) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 200; ++i) points.emplace_back(0.1 * i, 0.0, 0.1 * i);
  VariogramOptions o;
  o.bin_m = 1.0;
  o.max_lag_m = 10.0;
  o.short_lag_m = 2.0;
  o.short_bin_m = 0.25;
  const ExperimentalVariogram v = ComputeExperimentalVariogram(points, o);
  // 0.25 m bins up to 2 m, then 1 m bins up to 10 m.
  std::vector<double> lower;
  for (int i = 0; i < 8; ++i) lower.push_back(0.25 * i);
  for (int i = 2; i < 10; ++i) lower.push_back(i);
  ASSERT_EQ(v.lag_m.size(), lower.size());
  for (size_t i = 0; i < v.lag_m.size(); ++i) {
    const double width = i < 8 ? 0.25 : 1.0;
    EXPECT_GE(v.lag_m[i], lower[i] - 1e-9);
    EXPECT_LT(v.lag_m[i], lower[i] + width);
    EXPECT_GE(v.gamma[i], 0.5 * v.lag_m[i] * v.lag_m[i] - 1e-9);  // mean h^2 >= mean(h)^2
    EXPECT_LT(v.gamma[i], 0.5 * v.lag_m[i] * v.lag_m[i] + 0.05);
  }
}

// With a sparse subsample, the short lags still come from every point near each sampled one.
TEST(Variogram, ShortLagsPairTheSampleWithAllItsNeighbours) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 400; ++i) points.emplace_back(0.1 * i, 0.0, 0.1 * i);
  VariogramOptions o;
  o.max_points = 20;
  o.max_lag_m = 20.0;
  o.short_lag_m = 1.0;
  o.short_bin_m = 0.25;
  const ExperimentalVariogram with_short = ComputeExperimentalVariogram(points, o);
  o.short_lag_m = 0.0;
  const ExperimentalVariogram without = ComputeExperimentalVariogram(points, o);
  ASSERT_FALSE(with_short.lag_m.empty());
  // First bin, lags 0.1 and 0.2 m: up to 4 neighbours for each of the 20 sampled points.
  EXPECT_LT(with_short.lag_m[0], 0.25);
  EXPECT_GE(with_short.pairs[0], 60.0);
  EXPECT_NEAR(with_short.gamma[0], 0.5 * (0.01 + 0.04) / 2, 1e-3);
  auto close_pairs = [](const ExperimentalVariogram& v) {
    double n = 0.0;
    for (size_t i = 0; i < v.lag_m.size(); ++i) n += v.lag_m[i] < 1.0 ? v.pairs[i] : 0.0;
    return n;
  };
  // 20 sampled points along 40 m: a handful of pairs closer than 1 m among themselves.
  EXPECT_GT(close_pairs(with_short), 10.0 * close_pairs(without));
}

// Points whose noise differs (near and far ones of a station): each pair's two noise variances
// come out of its squared difference, and the bins are those of the noise-free surface. Left
// in, every bin is raised by the pairs' mean noise, which reads as relief at every lag.
TEST(Variogram, EachPointsOwnNoiseIsTakenOutOfItsPairs) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-30, 30);
  std::normal_distribution<double> unit(0.0, 1.0);
  auto surface = [](double x, double y) { return 0.05 * std::sin(x / 7.0) * std::cos(y / 5.0); };
  std::vector<Eigen::Vector3d> exact, noisy;
  std::vector<double> variances;
  for (int i = 0; i < 3000; ++i) {
    const double x = u(rng), y = u(rng);
    const double sigma = 0.002 + 0.0004 * std::hypot(x, y);  // 2 mm at the centre, 19 mm at 42 m
    exact.emplace_back(x, y, surface(x, y));
    noisy.emplace_back(x, y, surface(x, y) + sigma * unit(rng));
    variances.push_back(sigma * sigma);
  }
  VariogramOptions o;
  o.max_points = 3000;
  const ExperimentalVariogram truth = ComputeExperimentalVariogram(exact, o);
  const ExperimentalVariogram signal = ComputeExperimentalVariogram(noisy, o, variances);
  const ExperimentalVariogram raw = ComputeExperimentalVariogram(noisy, o);
  ASSERT_EQ(signal.gamma.size(), truth.gamma.size());
  ASSERT_EQ(signal.noise.size(), truth.gamma.size());
  double mean_noise = 0.0;
  for (const double v : variances) mean_noise += v / variances.size();
  for (size_t i = 0; i < truth.gamma.size(); ++i) {
    // A bin's mean scatters by sqrt(2) (gamma + noise) over the root of its pairs, and more at
    // short lags, whose pairs share their points.
    const double slack = 6.0 * (signal.noise[i] + truth.gamma[i]) / std::sqrt(signal.pairs[i]);
    EXPECT_NEAR(signal.gamma[i], truth.gamma[i], slack + 0.1 * truth.gamma[i])
        << "lag " << truth.lag_m[i];
    EXPECT_NEAR(signal.noise[i], mean_noise, 0.5 * mean_noise) << "lag " << truth.lag_m[i];
    EXPECT_GT(raw.gamma[i], truth.gamma[i] + 0.5 * mean_noise) << "lag " << truth.lag_m[i];
  }
}

// Two points matched in one window carry one error, which cancels in their difference: their
// pair's noise is none. Sites 1 m apart on a gentle surface, each seen as two points 0.1 m
// apart in one window (one pair per site): the shortest bin holds those twins alone, its noise
// is none and its gamma the surface's, not the surface's less the noise.
TEST(Variogram, NoiseTwoPointsShareCancelsInTheirDifference) {
  std::mt19937 rng(9);
  std::normal_distribution<double> unit(0.0, 1.0);
  auto surface = [](double x, double y) { return 0.3 * std::sin(x / 3.0) * std::cos(y / 4.0); };
  const double sigma = 0.02;
  std::vector<Eigen::Vector3d> points, exact;
  std::vector<double> variances;
  std::vector<PointMatch> matches;
  int site = 0;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j, ++site) {
      const double error = sigma * unit(rng);
      for (const double dx : {0.0, 0.1}) {
        const double x = i + dx, y = j;
        points.emplace_back(x, y, surface(x, y) + error);
        exact.emplace_back(x, y, surface(x, y));
        variances.push_back(sigma * sigma);
        matches.push_back({site, {{100, 100}, {10, 10}}});
      }
    }
  VariogramOptions o;
  o.max_points = 2000;
  const ExperimentalVariogram truth = ComputeExperimentalVariogram(exact, o);
  const ExperimentalVariogram shared = ComputeExperimentalVariogram(points, o, variances, matches);
  const ExperimentalVariogram independent = ComputeExperimentalVariogram(points, o, variances);
  ASSERT_FALSE(truth.gamma.empty());
  ASSERT_NEAR(truth.lag_m[0], 0.1, 1e-9);  // the first bin holds the twins alone
  EXPECT_NEAR(shared.noise[0], 0.0, 1e-12);
  EXPECT_NEAR(independent.noise[0], sigma * sigma, 1e-12);
  EXPECT_NEAR(shared.gamma[0], truth.gamma[0], 1e-12);
  EXPECT_EQ(independent.gamma[0], 0.0);  // the surface's 0.1 m less the noise: below zero
  // Beyond the twins, pairs of different sites: their noise counted in full either way.
  for (size_t i = 1; i < shared.noise.size(); ++i)
    EXPECT_NEAR(shared.noise[i], independent.noise[i], 0.05 * sigma * sigma) << shared.lag_m[i];
}

// A Gaussian model without a nugget is not chosen even where it would fit best.
TEST(Variogram, GaussianWithoutNuggetIsNotChosen) {
  ExperimentalVariogram e;
  for (double h = 0.125; h < 20.0; h += 0.25) {
    e.lag_m.push_back(h);
    e.gamma.push_back(1.0 - std::exp(-3.0 * h * h / 100.0));  // Gaussian, range 10 m, no nugget
    e.pairs.push_back(100.0);
  }
  EXPECT_EQ(FitVariogram(e, VariogramKind::kGaussian).kind, VariogramKind::kGaussian);
  EXPECT_LT(FitVariogram(e, VariogramKind::kGaussian).fit_error,
            FitVariogram(e, VariogramKind::kSpherical).fit_error);
  EXPECT_NE(FitVariogram(e).kind, VariogramKind::kGaussian);
}

ExperimentalVariogram FromModel(const VariogramModel& m) {
  ExperimentalVariogram e;
  for (double h = 0.5; h < 30; h += 1.0) {
    e.lag_m.push_back(h);
    e.gamma.push_back(m(h));
    e.pairs.push_back(100);
  }
  return e;
}

TEST(Variogram, FitRecoversEachKindAndItsParameters) {
  for (VariogramKind kind : {VariogramKind::kSpherical, VariogramKind::kExponential,
                             VariogramKind::kGaussian, VariogramKind::kMatern32}) {
    VariogramModel truth;
    truth.kind = kind;
    truth.nugget = 0.01;
    truth.partial_sill = 0.8;
    truth.range_m = 12.0;
    const VariogramModel fit = FitVariogram(FromModel(truth));
    EXPECT_EQ(fit.kind, kind) << VariogramKindName(kind);
    EXPECT_NEAR(fit.range_m, 12.0, 0.3) << VariogramKindName(kind);
    EXPECT_NEAR(fit.partial_sill, 0.8, 0.02) << VariogramKindName(kind);
    EXPECT_NEAR(fit.nugget, 0.01, 0.005) << VariogramKindName(kind);
  }
}

TEST(Variogram, TooFewBinsGiveAnInfiniteFitError) {
  ExperimentalVariogram e;
  e.lag_m = {1.0, 2.0};
  e.gamma = {0.1, 0.2};
  e.pairs = {10, 10};
  EXPECT_TRUE(std::isinf(FitVariogram(e).fit_error));
}

}  // namespace
}  // namespace ts
