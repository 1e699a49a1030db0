#pragma once
// The semivariogram of ground heights for ordinary kriging: the experimental variogram from
// pairs of points binned by horizontal distance, and a model fitted to it,
//   gamma(h) = nugget + partial_sill * f(h / range)
// with f spherical, exponential (practical range: 95 % of the sill at `range`), Gaussian or
// Matern 3/2 (likewise; parabolic at the origin like the Gaussian, but a surface differentiable
// only once), whichever fits best (kriging.h chooses among the fits by cross-validation
// instead). For each model the range is searched on a fine grid and,
// given the range, nugget and partial sill follow from weighted least squares (Cressie's
// weights: pairs in the bin over gamma squared), both kept non-negative.
#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/dem/shared_noise.h"

namespace ts {

struct ExperimentalVariogram {
  std::vector<double> lag_m;  // mean distance of the pairs in each bin
  std::vector<double> gamma;  // half the mean squared height difference, less the noise below
  std::vector<double> pairs;  // pairs in the bin
  // The pairs' mean noise variance taken out of gamma (zero without noise variances): gamma
  // plus this is what the bin's squared differences scatter about, and weighs its fit.
  std::vector<double> noise;
};

struct VariogramOptions {
  double bin_m = 1.0;
  double max_lag_m = 20.0;
  int max_points = 2000;  // the variogram is taken from an even random subsample
  // Below short_lag_m, each sampled point is paired with every point (not only the sampled
  // ones) within short_lag_m, in bins of short_bin_m: a sparse subsample has almost no close
  // pairs, and the nugget was then extrapolated from 1 m lags, taking real short-range
  // relief for noise (kriging then smoothed it away: a 0.5 m bowl came out 6 mm shallow).
  double short_lag_m = 2.0;  // 0: no short-lag pairs
  double short_bin_m = 0.25;
  uint32_t seed = 1;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("bin_m", self.bin_m, {"lag bin width", "m", 0.01, 50});
    v("max_lag_m", self.max_lag_m, {"largest lag fitted", "m", 0.1, 500});
    v("max_points", self.max_points,
      {"points in the random subsample the variogram is taken from", "", 3, 100000});
    v("short_lag_m", self.short_lag_m, {"short-lag pairs below this (0: none)", "m", 0, 100});
    v("short_bin_m", self.short_bin_m, {"their bin width", "m", 0, 10});
    v("seed", self.seed, {"subsample seed", "", 0, 4294967295});
  }
  bool Check(std::string* why) const;
};

// noise_variances_m2: empty, or each point's own height variance. Then each pair's squared
// difference less its two noise variances is what the bins average: the variogram of the
// surface, not of the points. Kriging puts each point's noise on its own diagonal; left in the
// variogram too, a flat field's matching noise, correlated over a window's footprint, reads as
// relief, and the std counts the noise twice. With each point's match (shared_noise.h), a
// pair's noise is less what the two points share: it cancels in their difference.
ExperimentalVariogram ComputeExperimentalVariogram(
    const std::vector<Eigen::Vector3d>& points, const VariogramOptions& options,
    const std::vector<double>& noise_variances_m2 = {},
    const std::vector<PointMatch>& matches = {});

enum class VariogramKind { kSpherical, kExponential, kGaussian, kMatern32 };
const char* VariogramKindName(VariogramKind kind);

struct VariogramModel {
  VariogramKind kind = VariogramKind::kSpherical;
  double nugget = 0.0;
  double partial_sill = 1.0;
  double range_m = 10.0;
  double fit_error = 0.0;  // weighted sum of squared misfits of the fit
  double operator()(double h_m) const;
  // Covariance of the noise-free surface, partial_sill - (gamma(h) - nugget) for h > 0; the
  // nugget is the variance of the points' own noise, added on the data's diagonal only.
  double SignalCovariance(double h_m) const;
  double Sill() const { return nugget + partial_sill; }
};

// The best of the three kinds; a Gaussian only with a nugget of at least 1 % of its sill. Needs at
// least three non-empty bins (else a linear-looking spherical model through the bins is returned
// with fit_error = infinity).
VariogramModel FitVariogram(const ExperimentalVariogram& experimental);
VariogramModel FitVariogram(const ExperimentalVariogram& experimental, VariogramKind kind);
// One fit of each kind that FitVariogram(experimental) may choose from, the spherical first,
// and the one of them that FitVariogram chooses.
std::vector<VariogramModel> FitVariogramOfEachKind(const ExperimentalVariogram& experimental);
VariogramModel BestFit(const std::vector<VariogramModel>& fits);

}  // namespace ts
