#include "processing/gravity/prism.h"

#include <cmath>

namespace ts {
namespace {

// ln(a + r2) - ln(a + r1) with r_k = sqrt(a^2 + b2 + z_k^2), b2 > 0, without forming either
// logarithm: for a prism much wider than deep the two are huge and nearly equal. dr = r2 - r1.
double LogDifference(double a, double b2, double z1, double z2, double r1, double dr) {
  if (a >= 0.0) return std::log1p(dr / (a + r1));
  // a < 0: ln(a + r) = ln((b2 + z^2) / (r - a)), free of cancellation. The ratio of the
  // b2 + z^2 terms by log1p where it is near 1, directly where it is not (b2 << z^2: near
  // the edge through the point, where log1p's argument would round to -1).
  const double q = (z2 * z2 - z1 * z1) / (b2 + z1 * z1);
  const double ratio_log = q > -0.5 ? std::log1p(q) : std::log((b2 + z2 * z2) / (b2 + z1 * z1));
  return ratio_log - std::log1p(dr / (r1 - a));
}

double AtanTerm(double x, double y, double z, double r) {
  return z == 0.0 ? 0.0 : z * std::atan(x * y / (z * r));  // z atan(...) -> 0 as z -> 0
}

// The corner function F(x, y, z) = x ln(y + r) + y ln(x + r) - z atan(x y / (z r)) of one
// vertical edge of the prism, differenced between its two ends: F(x, y, z2) - F(x, y, z1).
// A term whose factor (x or y) is 0 is 0 (its limit on the prism's edges and faces).
double EdgeTerm(double x, double y, double z1, double z2) {
  const double x2 = x * x, y2 = y * y;
  const double r1 = std::sqrt(x2 + y2 + z1 * z1), r2 = std::sqrt(x2 + y2 + z2 * z2);
  const double dr = r1 + r2 > 0.0 ? (z2 * z2 - z1 * z1) / (r1 + r2) : 0.0;
  double f = 0.0;
  if (x != 0.0) f += x * LogDifference(y, x2, z1, z2, r1, dr);
  if (y != 0.0) f += y * LogDifference(x, y2, z1, z2, r1, dr);
  return f - (AtanTerm(x, y, z2, r2) - AtanTerm(x, y, z1, r1));
}

}  // namespace

double PrismDownwardAttraction(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                               double density) {
  // g_up = G rho sum_{ijk} (-1)^{i+j+k} F = -G rho sum_{ij} (-1)^{i+j} EdgeTerm; downward is
  // its negative.
  double sum = 0.0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const double sign = (i + j) % 2 == 0 ? 1.0 : -1.0;
      sum += sign * EdgeTerm(i ? hi.x() : lo.x(), j ? hi.y() : lo.y(), lo.z(), hi.z());
    }
  return kGravitationalConstant * density * sum;
}

double PrismDownwardAttractionFarField(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                       double density_kg_m3) {
  // Four vertical line masses at the 2 x 2 Gauss-Legendre points of the cross-section.
  const double cx = 0.5 * (lo.x() + hi.x()), cy = 0.5 * (lo.y() + hi.y());
  const double dx = 0.5 * (hi.x() - lo.x()) / std::sqrt(3.0);
  const double dy = 0.5 * (hi.y() - lo.y()) / std::sqrt(3.0);
  const double line = kGravitationalConstant * density_kg_m3 * 0.25 * (hi.x() - lo.x()) *
                      (hi.y() - lo.y());  // G rho A / 4 per line
  double g_up = 0.0;
  for (const double x : {cx - dx, cx + dx})
    for (const double y : {cy - dy, cy + dy}) {
      const double r2 = x * x + y * y;
      g_up +=
          line * (1.0 / std::sqrt(r2 + lo.z() * lo.z()) - 1.0 / std::sqrt(r2 + hi.z() * hi.z()));
    }
  return -g_up;
}

}  // namespace ts
