#include "processing/geometry/theoretical_accuracy.h"

#include <cmath>
#include <stdexcept>

namespace ts {

bool TheoreticalAccuracyOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!(range_max_m >= range_min_m))
    err = "range_max_m must not be below range_min_m";
  else if ((range_max_m - range_min_m) / range_step_m > 1e5)
    err = "too many rows (more than 100000)";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

std::vector<AccuracyRow> TheoreticalAccuracy(double baseline_m, double principal_distance_px,
                                             const TheoreticalAccuracyOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("theoretical accuracy: " + why);
  if (!(baseline_m > 0.0) || !(principal_distance_px > 0.0))
    throw std::invalid_argument("theoretical accuracy: baseline and focal length must be > 0");
  const double f = principal_distance_px;
  std::vector<AccuracyRow> rows;
  // Index-based so that floating-point steps cannot drop the last row.
  const int n =
      static_cast<int>(std::floor((o.range_max_m - o.range_min_m) / o.range_step_m + 1e-9));
  for (int i = 0; i <= n; ++i) {
    const double y = o.range_min_m + i * o.range_step_m;
    const double depth_factor = y * y / (baseline_m * f);  // m per px of parallax
    AccuracyRow row;
    row.range_m = y;
    row.sigma_y_m = depth_factor * o.sigma_parallax_px;
    row.sigma_x_m = std::hypot(depth_factor * (o.image_x_px / f) * o.sigma_parallax_px,
                               (y / f) * o.sigma_image_px);
    row.sigma_z_m = std::hypot(depth_factor * (o.image_y_px / f) * o.sigma_parallax_px,
                               (y / f) * o.sigma_image_px);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace ts
