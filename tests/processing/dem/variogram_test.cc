#include "processing/dem/variogram.h"

#include <gtest/gtest.h>

namespace ts {
namespace {

// z = x along a line: every pair at distance h has gamma = h^2 / 2.
TEST(Variogram, ExperimentalOfALinearRampIsHalfTheSquaredLag) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 200; ++i) points.emplace_back(0.1 * i, 0.0, 0.1 * i);
  VariogramOptions o;
  o.bin_m = 1.0;
  o.max_lag_m = 10.0;
  const ExperimentalVariogram v = ComputeExperimentalVariogram(points, o);
  ASSERT_EQ(v.lag_m.size(), 10u);
  for (size_t i = 0; i < v.lag_m.size(); ++i) {
    EXPECT_GE(v.lag_m[i], static_cast<double>(i));
    EXPECT_LT(v.lag_m[i], i + 1.0);
    EXPECT_GT(v.gamma[i], 0.5 * v.lag_m[i] * v.lag_m[i]);  // mean of h^2 exceeds mean(h)^2
    EXPECT_LT(v.gamma[i], 0.5 * v.lag_m[i] * v.lag_m[i] + 0.05);
  }
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
  for (VariogramKind kind :
       {VariogramKind::kSpherical, VariogramKind::kExponential, VariogramKind::kGaussian}) {
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
