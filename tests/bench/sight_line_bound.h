#pragma once
// What the lines of sight prove about a DEM (issue 22): every matched point of the ground was
// seen, so the terrain between its camera and it lies below that line. A DEM that stands above
// a line of sight where the line passes over it claims ground the cameras saw through.
// Only points on the true ground (within 0.3 m of it) count: a mismatched point's ray may have
// seen other ground. Two kinds of line:
//  - the matched line, to the point as matched, up to where process lets it count (its range
//    sigma, free_space.h): whether the DEM keeps to the lines process had;
//  - the true line, along the same ray to where it first meets the true ground: whether the
//    DEM stands where the cameras truly saw through. A point matched short of the ground (a
//    far wall's window matched a pixel or two off) raises the DEM into that space.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "processing/cloud/point_cloud.h"
#include "processing/dem/free_space.h"
#include "processing/io/raster.h"

namespace ts::bench {

// Where the ray from eye through point first meets the truth (bisected to a millimetre), or
// the point itself if the ray passes 10 m beyond it without doing so.
inline Eigen::Vector3d TrueSightLineEnd(const Raster& truth, const Eigen::Vector3d& eye,
                                        const Eigen::Vector3d& point) {
  const Eigen::Vector3d d = point - eye;
  const double run = d.head<2>().norm(), step = 0.5 * truth.cell_m / run;
  auto under = [&](double t) {  // the ray at t lies below the true ground
    const Eigen::Vector3d q = eye + t * d;
    const double ground = truth.Interpolate(q.x(), q.y());
    return std::isfinite(ground) && q.z() < ground;
  };
  for (double t = step; t < 1.0 + 10.0 / run; t += step) {
    if (!under(t)) continue;
    double above = t - step, below = t;
    while ((below - above) * run > 1e-3) {
      const double mid = 0.5 * (above + below);
      (under(mid) ? below : above) = mid;
    }
    return eye + above * d;
  }
  return point;
}

struct SightLineViolations {
  int cells = 0;  // DEM cells with data that some line of sight passed over
  int above = 0;  // of them, standing above the lowest line by more than the margin
  double max_above_m = 0.0;
};

enum class SightLineEnd { kMatched, kTrue };

// camera_of(point): the centre, in L, of the camera that saw it.
inline SightLineViolations CheckSightLines(
    const Raster& dem, const Raster& truth, const PointCloud& cloud,
    const std::function<Eigen::Vector3d(const CloudPoint&)>& camera_of, SightLineEnd end,
    double margin_m = 0.1) {
  // Per cell: how far the DEM (interpolated where the line passes) rose above a line.
  Raster excess = Raster::Make(dem.min_x_m, dem.max_y_m, dem.cell_m, dem.cols, dem.rows,
                               -std::numeric_limits<float>::infinity());
  for (const CloudPoint& p : cloud) {
    const double ground = truth.Interpolate(p.position_m.x(), p.position_m.y());
    if (!(std::abs(p.position_m.z() - ground) < 0.3)) continue;
    const Eigen::Vector3d eye = camera_of(p);
    const Eigen::Vector3d d =
        (end == SightLineEnd::kTrue ? TrueSightLineEnd(truth, eye, p.position_m) : p.position_m) -
        eye;
    const double run = d.head<2>().norm();
    // Up to a cell short of the line's end (the cell it lies in holds it), a matched line also
    // its range sigmas short.
    double end_gap = dem.cell_m;
    if (end == SightLineEnd::kMatched) {
      const Eigen::Vector3d ray = d.normalized();
      const double range_sigma = std::sqrt(ray.dot(p.covariance_m2.cast<double>() * ray));
      end_gap = std::max(end_gap, FreeSpaceOptions{}.end_sigmas * range_sigma * run / d.norm());
    }
    for (double s = 0.5 * dem.cell_m; s < run - end_gap; s += 0.5 * dem.cell_m) {
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
