#pragma once
// What the lines of sight prove about a DEM (issue 22): every matched point of the ground was
// seen, so the terrain between its camera and it lies below that line. A DEM that stands above
// a line of sight where the line passes over it claims ground the cameras saw through.
// For the benchmarks: only points on the true ground (within 0.3 m of it) count, so that a
// mismatched point does not make a false line.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "processing/cloud/point_cloud.h"
#include "processing/io/raster.h"

namespace ts::bench {

struct SightLineViolations {
  int cells = 0;  // DEM cells with data that some line of sight passed over
  int above = 0;  // of them, standing above the lowest line by more than the margin
  double max_above_m = 0.0;
};

// camera_of(point): the centre, in L, of the camera that saw it.
inline SightLineViolations CheckSightLines(
    const Raster& dem, const Raster& truth, const PointCloud& cloud,
    const std::function<Eigen::Vector3d(const CloudPoint&)>& camera_of, double margin_m = 0.1) {
  // Per cell: how far the DEM (interpolated where the line passes) rose above a line.
  Raster excess = Raster::Make(dem.min_x_m, dem.max_y_m, dem.cell_m, dem.cols, dem.rows,
                               -std::numeric_limits<float>::infinity());
  for (const CloudPoint& p : cloud) {
    const double ground = truth.Interpolate(p.position_m.x(), p.position_m.y());
    if (!(std::abs(p.position_m.z() - ground) < 0.3)) continue;
    const Eigen::Vector3d eye = camera_of(p);
    const Eigen::Vector3d d = p.position_m - eye;
    const double run = d.head<2>().norm();
    // Up to a cell short of the point: the cell it lies in holds it.
    for (double s = 0.5 * dem.cell_m; s < run - dem.cell_m; s += 0.5 * dem.cell_m) {
      const Eigen::Vector3d q = eye + d * (s / run);
      int row = 0, col = 0;
      if (!dem.CellOf(q.x(), q.y(), &row, &col)) continue;
      const double h = dem.Interpolate(q.x(), q.y());
      if (!std::isfinite(h)) continue;
      float& e = excess.at(row, col);
      e = std::max(e, static_cast<float>(h - q.z()));
    }
  }
  SightLineViolations v;
  for (const float e : excess.values) {
    if (!std::isfinite(e)) continue;
    ++v.cells;
    if (e > margin_m) ++v.above, v.max_above_m = std::max(v.max_above_m, double(e));
  }
  return v;
}

}  // namespace ts::bench
