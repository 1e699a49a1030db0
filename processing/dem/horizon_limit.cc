#include "processing/dem/horizon_limit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "processing/cloud/grid_index.h"
#include "processing/common/angles.h"

namespace ts {

bool HorizonLimitOptions::Check(std::string* why) const {
  std::string err;
  if (!(near_m > 0.0) || !(edge_m > near_m))
    err = "need 0 < near_m < edge_m";
  else if (!(bin_half_width_deg > 0.0 && bin_half_width_deg <= 10.0))
    err = "bin_half_width_deg must be in (0, 10]";
  else if (!(tolerance_m >= 0.0))
    err = "tolerance_m must not be negative";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

constexpr int kBins = 3600;  // azimuth bins of 0.1 degree
constexpr double kBinRad = 2.0 * M_PI / kBins;

int BinOf(double azimuth) {
  const int b = static_cast<int>(std::floor((azimuth + M_PI) / kBinRad));
  return ((b % kBins) + kBins) % kBins;
}

// The lines of sight from the viewpoint by azimuth bin, each bin by distance with the highest
// line so far (as rise over run) and whether a ground point set it.
class Horizons {
 public:
  Horizons(const std::vector<Eigen::Vector3d>& points, const std::vector<uint8_t>& ground,
           const Eigen::Vector3d& viewpoint)
      : bins_(kBins) {
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d d = points[i] - viewpoint;
      const double run = std::hypot(d.x(), d.y());
      if (!(run > 0.5)) continue;
      bins_[BinOf(std::atan2(d.y(), d.x()))].push_back(
          {static_cast<float>(run), static_cast<float>(d.z() / run), ground[i] != 0});
    }
    for (std::vector<Sight>& bin : bins_) {
      std::sort(bin.begin(), bin.end(),
                [](const Sight& a, const Sight& b) { return a.distance < b.distance; });
      for (size_t k = 1; k < bin.size(); ++k)
        if (bin[k - 1].slope >= bin[k].slope)
          bin[k].slope = bin[k - 1].slope, bin[k].ground = bin[k - 1].ground;
    }
  }

  // The highest line of sight to a point nearer than `distance`, within +-half bins of the
  // azimuth; false when there is none.
  bool Highest(double azimuth, double distance, int half, double* slope, bool* ground) const {
    const int centre = BinOf(azimuth);
    bool found = false;
    for (int k = -half; k <= half; ++k) {
      const std::vector<Sight>& bin = bins_[((centre + k) % kBins + kBins) % kBins];
      const auto after = std::lower_bound(bin.begin(), bin.end(), distance,
                                          [](const Sight& s, double d) { return s.distance < d; });
      if (after == bin.begin()) continue;
      const Sight& nearer = *(after - 1);
      if (!found || nearer.slope > *slope) *slope = nearer.slope, *ground = nearer.ground;
      found = true;
    }
    return found;
  }

 private:
  struct Sight {
    float distance;
    float slope;  // highest so far, from here
    bool ground;
  };
  std::vector<std::vector<Sight>> bins_;
};

}  // namespace

HorizonLimitResult LimitToHorizon(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<uint8_t>& ground,
                                  const Eigen::Vector3d& viewpoint, const HorizonLimitOptions& o,
                                  Raster* dem) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("HorizonLimitOptions: " + why);
  if (ground.size() != points.size())
    throw std::invalid_argument("LimitToHorizon: one ground flag per point");
  HorizonLimitResult result;
  if (!o.enabled) return result;
  std::vector<Eigen::Vector3d> ground_points;
  for (size_t i = 0; i < points.size(); ++i)
    if (ground[i]) ground_points.push_back(points[i]);
  if (ground_points.empty()) return result;
  const GridIndex grid(ground_points, 1.0);
  const Horizons horizons(points, ground, viewpoint);
  const int half = static_cast<int>(std::ceil(o.bin_half_width_deg * M_PI / 180.0 / kBinRad));
  const int reach = static_cast<int>(std::ceil(o.edge_m));
  const int near_cells = static_cast<int>(std::ceil(o.near_m));
  double lowered = 0.0;
  for (int row = 0; row < dem->rows; ++row)
    for (int col = 0; col < dem->cols; ++col) {
      float& z = dem->at(row, col);
      if (Raster::IsNoData(z)) continue;
      const double x = dem->CellCentreX(col), y = dem->CellCentreY(row);
      // Seen: a ground point within near_m. Beyond the edge: the ground within edge_m (one
      // direction per grid cell) leaves a gap of more than 180 degrees.
      const int c0 = grid.ColOf(x), r0 = grid.RowOf(y);
      bool seen = false;
      for (int r = r0 - near_cells; r <= r0 + near_cells && !seen; ++r)
        for (int c = c0 - near_cells; c <= c0 + near_cells && !seen; ++c) {
          if (!grid.Inside(c, r)) continue;
          for (const int* i = grid.begin(c, r); i != grid.end(c, r) && !seen; ++i)
            seen = std::hypot(ground_points[*i].x() - x, ground_points[*i].y() - y) <= o.near_m;
        }
      if (seen) continue;
      std::vector<double> directions;
      for (int r = r0 - reach; r <= r0 + reach; ++r)
        for (int c = c0 - reach; c <= c0 + reach; ++c) {
          if (!grid.Inside(c, r) || grid.Count(c, r) == 0) continue;
          const Eigen::Vector3d& p = ground_points[*grid.begin(c, r)];
          if (std::hypot(p.x() - x, p.y() - y) <= o.edge_m)
            directions.push_back(std::atan2(p.y() - y, p.x() - x));
        }
      if (directions.size() < 3 || LargestAngularGap(std::move(directions)) <= M_PI) continue;
      const double dx = x - viewpoint.x(), dy = y - viewpoint.y(), run = std::hypot(dx, dy);
      double slope = 0.0;
      bool by_ground = false;
      if (!horizons.Highest(std::atan2(dy, dx), run - 0.5 * dem->cell_m, half, &slope,
                            &by_ground) ||
          !by_ground)
        continue;
      const double horizon = viewpoint.z() + run * slope;
      if (z <= horizon + o.tolerance_m) continue;
      lowered += z - horizon;
      z = static_cast<float>(horizon);
      ++result.cells_lowered;
    }
  if (result.cells_lowered > 0) result.mean_lowering_m = lowered / result.cells_lowered;
  return result;
}

}  // namespace ts
