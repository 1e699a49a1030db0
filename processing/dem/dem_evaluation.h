#pragma once
// How good a DEM is: its coverage around the station, and (with a reference DEM, e.g. the
// simulator's true bare earth) its height errors over the cells with data.
#include <Eigen/Core>
#include <cmath>
#include <nlohmann/json.hpp>

#include "processing/io/raster.h"

namespace ts {

// Share of cells with data among those whose centre is within radius_m of the station
// (radius_m <= 0: all cells of the raster).
double DemCoverage(const Raster& dem, const Eigen::Vector2d& station_xy_m, double radius_m);

struct DemEvaluation {
  double rmse_m = 0.0;  // over every cell of the DEM (the 60 m square)
  // Over the cells whose centre lies within 30 m of the station: the near region the terrain
  // correction needs and issue 22's targets are set on (NaN: none compared).
  double rmse_30m_m = NAN;
  double bias_m = 0.0;     // mean of DEM - reference
  double p95_abs_m = 0.0;  // 95th percentile of |DEM - reference|
  double max_abs_m = 0.0;
  double coverage_30m = 0.0;
  double coverage_square = 0.0;  // the whole DEM raster (the 60 m square)
  int cells_compared = 0;
  // With the DEM's standard deviation grid: how honest it is. RMS of error / std (1 when the
  // std is right) and the share of cells whose error is within 2 std (~95 % when it is).
  double std_ratio_rms = NAN;
  double within_2std = NAN;
  nlohmann::json ToJson() const;
};

// Compares every DEM cell with data with the reference interpolated at its centre (same
// frame). Cells the reference does not cover are left out of the errors.
DemEvaluation EvaluateDem(const Raster& dem, const Raster& reference,
                          const Eigen::Vector2d& station_xy_m, const Raster* std_dev = nullptr);

}  // namespace ts
