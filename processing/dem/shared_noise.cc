#include "processing/dem/shared_noise.h"

#include <algorithm>
#include <cmath>

namespace ts {

namespace {

// The share of one axis two windows have in common, over the geometric mean of their widths.
double AxisOverlap(float centre_a, float half_a, float centre_b, float half_b) {
  const double lo = std::max(centre_a - half_a, centre_b - half_b) - 0.5;
  const double hi = std::min(centre_a + half_a, centre_b + half_b) + 0.5;
  return std::max(0.0, hi - lo) / std::sqrt((2.0 * half_a + 1.0) * (2.0 * half_b + 1.0));
}

}  // namespace

double SharedNoiseCorrelation(const PointMatch& a, const PointMatch& b) {
  if (a.pair < 0 || a.pair != b.pair) return 0.0;
  const MatchWindow &u = a.window, &v = b.window;
  if (u.half_size_px.isZero() || v.half_size_px.isZero()) return 0.0;
  return AxisOverlap(u.centre_px.x(), u.half_size_px.x(), v.centre_px.x(), v.half_size_px.x()) *
         AxisOverlap(u.centre_px.y(), u.half_size_px.y(), v.centre_px.y(), v.half_size_px.y());
}

double SharedNoiseCovariance(const PointMatch& a, double variance_a, const PointMatch& b,
                             double variance_b) {
  const double rho = SharedNoiseCorrelation(a, b);
  return rho > 0.0 ? rho * std::sqrt(variance_a * variance_b) : 0.0;
}

}  // namespace ts
