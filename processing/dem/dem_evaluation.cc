#include "processing/dem/dem_evaluation.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ts {

namespace {
constexpr double kNearRegionM = 30.0;  // the near region the terrain correction needs
}  // namespace

double DemCoverage(const Raster& dem, const Eigen::Vector2d& station_xy, double radius_m) {
  int total = 0, with_data = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const Eigen::Vector2d centre(dem.CellCentreX(c), dem.CellCentreY(r));
      if (radius_m > 0 && (centre - station_xy).norm() > radius_m) continue;
      ++total;
      with_data += !Raster::IsNoData(dem.at(r, c));
    }
  return total ? static_cast<double>(with_data) / total : 0.0;
}

DemEvaluation EvaluateDem(const Raster& dem, const Raster& reference,
                          const Eigen::Vector2d& station_xy, const Raster* std_dev) {
  DemEvaluation e;
  std::vector<double> abs_errors;
  double sum = 0.0, sum2 = 0.0, ratio2 = 0.0, near_sum2 = 0.0;
  int with_std = 0, within = 0, near = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      if (Raster::IsNoData(dem.at(r, c))) continue;
      const double truth = reference.Interpolate(dem.CellCentreX(c), dem.CellCentreY(r));
      if (!std::isfinite(truth)) continue;
      const double d = dem.at(r, c) - truth;
      sum += d, sum2 += d * d;
      if ((Eigen::Vector2d(dem.CellCentreX(c), dem.CellCentreY(r)) - station_xy).norm() <=
          kNearRegionM)
        near_sum2 += d * d, ++near;
      abs_errors.push_back(std::abs(d));
      const float s = std_dev ? std_dev->at(r, c) : Raster::kNoData;
      if (!Raster::IsNoData(s) && s > 0.0f) {
        ++with_std;
        ratio2 += (d / s) * (d / s);
        within += std::abs(d) <= 2.0 * s;
      }
    }
  e.cells_compared = static_cast<int>(abs_errors.size());
  if (!abs_errors.empty()) {
    const double n = static_cast<double>(abs_errors.size());
    e.rmse_m = std::sqrt(sum2 / n);
    e.bias_m = sum / n;
    std::sort(abs_errors.begin(), abs_errors.end());
    e.p95_abs_m = abs_errors[std::min(abs_errors.size() - 1, static_cast<size_t>(0.95 * n))];
    e.max_abs_m = abs_errors.back();
  }
  if (near > 0) e.rmse_30m_m = std::sqrt(near_sum2 / near);
  if (with_std > 0) {
    e.std_ratio_rms = std::sqrt(ratio2 / with_std);
    e.within_2std = static_cast<double>(within) / with_std;
  }
  e.coverage_30m = DemCoverage(dem, station_xy, kNearRegionM);
  e.coverage_square = DemCoverage(dem, station_xy, 0.0);
  return e;
}

nlohmann::json DemEvaluation::ToJson() const {
  return {{"dem_rmse_m", rmse_m},
          {"dem_rmse_30m_m", std::isfinite(rmse_30m_m) ? nlohmann::json(rmse_30m_m) : nullptr},
          {"dem_bias_m", bias_m},
          {"dem_p95_abs_m", p95_abs_m},
          {"dem_max_abs_m", max_abs_m},
          {"coverage_30m", coverage_30m},
          {"coverage_60m_square", coverage_square},
          {"cells_compared", cells_compared},
          {"std_ratio_rms", std::isfinite(std_ratio_rms) ? nlohmann::json(std_ratio_rms) : nullptr},
          {"within_2std", std::isfinite(within_2std) ? nlohmann::json(within_2std) : nullptr}};
}

}  // namespace ts
