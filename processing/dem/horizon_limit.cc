#include "processing/dem/horizon_limit.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <stdexcept>

#include "processing/cloud/grid_index.h"
#include "processing/common/angles.h"

namespace ts {

bool HorizonLimitOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!(edge_m > near_m)) err = "need near_m < edge_m";
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

// What set a line of sight.
enum class Setter : uint8_t { kOther, kGround, kObject };

// The lines of sight from the viewpoint by azimuth bin, each bin by distance with the highest
// line so far (as rise over run) and what set it.
class Horizons {
 public:
  Horizons(const std::vector<Eigen::Vector3d>& points, const std::vector<Setter>& setter,
           const Eigen::Vector3d& viewpoint)
      : bins_(kBins) {
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d d = points[i] - viewpoint;
      const double run = std::hypot(d.x(), d.y());
      if (!(run > 0.5)) continue;
      bins_[BinOf(std::atan2(d.y(), d.x()))].push_back(
          {static_cast<float>(run), static_cast<float>(d.z() / run),
           static_cast<float>(d.z() / run), setter[i]});
    }
    for (std::vector<Sight>& bin : bins_) {
      std::sort(bin.begin(), bin.end(),
                [](const Sight& a, const Sight& b) { return a.distance < b.distance; });
      for (size_t k = bin.size(); k-- > 1;)
        bin[k - 1].lowest_beyond = std::min(bin[k - 1].lowest_beyond, bin[k].lowest_beyond);
      for (size_t k = 1; k < bin.size(); ++k)
        if (bin[k - 1].slope >= bin[k].slope)
          bin[k].slope = bin[k - 1].slope, bin[k].setter = bin[k - 1].setter;
    }
  }

  // The lowest line of sight to a point farther than `distance`, within +-half bins of the
  // azimuth: it passed over everything nearer; false when there is none.
  bool LowestBeyond(double azimuth, double distance, int half, double* slope) const {
    const int centre = BinOf(azimuth);
    bool found = false;
    for (int k = -half; k <= half; ++k) {
      const std::vector<Sight>& bin = bins_[((centre + k) % kBins + kBins) % kBins];
      const auto beyond = std::upper_bound(bin.begin(), bin.end(), distance,
                                           [](double d, const Sight& s) { return d < s.distance; });
      if (beyond == bin.end()) continue;
      if (!found || beyond->lowest_beyond < *slope) *slope = beyond->lowest_beyond;
      found = true;
    }
    return found;
  }

  // The highest line of sight to a point nearer than `distance`, within +-half bins of the
  // azimuth; false when there is none.
  bool Highest(double azimuth, double distance, int half, double* slope, Setter* setter) const {
    const int centre = BinOf(azimuth);
    bool found = false;
    for (int k = -half; k <= half; ++k) {
      const std::vector<Sight>& bin = bins_[((centre + k) % kBins + kBins) % kBins];
      const auto after = std::lower_bound(bin.begin(), bin.end(), distance,
                                          [](const Sight& s, double d) { return s.distance < d; });
      if (after == bin.begin()) continue;
      const Sight& nearer = *(after - 1);
      if (!found || nearer.slope > *slope) *slope = nearer.slope, *setter = nearer.setter;
      found = true;
    }
    return found;
  }

 private:
  struct Sight {
    float distance;
    float slope;          // highest so far, from here
    float lowest_beyond;  // lowest from here on, outwards
    Setter setter;
  };
  std::vector<std::vector<Sight>> bins_;
};

// Ground points set ground horizons; other points object horizons when they stand
// min_object_height_m or more above the DEM.
std::vector<Setter> SettersOf(const std::vector<Eigen::Vector3d>& points,
                              const std::vector<uint8_t>& ground, const Raster& dem,
                              double min_object_height_m) {
  std::vector<Setter> setter(points.size(), Setter::kOther);
  for (size_t i = 0; i < points.size(); ++i) {
    if (ground[i]) {
      setter[i] = Setter::kGround;
      continue;
    }
    int row = 0, col = 0;
    if (!dem.CellOf(points[i].x(), points[i].y(), &row, &col)) continue;
    const float z = dem.at(row, col);
    if (!Raster::IsNoData(z) && points[i].z() - z >= min_object_height_m)
      setter[i] = Setter::kObject;
  }
  return setter;
}

}  // namespace

HorizonLimitResult LimitToHorizon(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<uint8_t>& ground,
                                  const Eigen::Vector3d& viewpoint, const HorizonLimitOptions& o,
                                  Raster* dem, Raster* std, double data_reach_m) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("HorizonLimitOptions: " + why);
  if (ground.size() != points.size())
    throw std::invalid_argument("LimitToHorizon: one ground flag per point");
  if (std && (std->rows != dem->rows || std->cols != dem->cols))
    throw std::invalid_argument("LimitToHorizon: the std grid differs from the DEM's");
  HorizonLimitResult result;
  if (!o.enabled) return result;
  std::vector<Eigen::Vector3d> ground_points;
  for (size_t i = 0; i < points.size(); ++i)
    if (ground[i]) ground_points.push_back(points[i]);
  if (ground_points.empty()) return result;
  const GridIndex grid(ground_points, 1.0);
  const Horizons horizons(points, SettersOf(points, ground, *dem, o.min_object_height_m),
                          viewpoint);
  // The terrain's own horizons, for cells behind an object that a brow hides as well.
  const Horizons ground_horizons(
      ground_points, std::vector<Setter>(ground_points.size(), Setter::kGround), viewpoint);
  const int half = static_cast<int>(std::ceil(o.bin_half_width_deg * M_PI / 180.0 / kBinRad));
  // The highest line of `from` over the cell centre (x, y), to a point nearer than the cell: its
  // height there and what set it; false when there is none.
  auto line_over = [&](const Horizons& from, double x, double y, double* height, Setter* setter) {
    const double dx = x - viewpoint.x(), dy = y - viewpoint.y(), run = std::hypot(dx, dy);
    double slope = 0.0;
    if (!from.Highest(std::atan2(dy, dx), run - 0.5 * dem->cell_m, half, &slope, setter))
      return false;
    *height = viewpoint.z() + run * slope;
    return true;
  };
  // The lowest line over the cell centre to a point a cell or more beyond it: its height there;
  // false when nothing was seen beyond.
  auto line_beyond = [&](double x, double y, double* height) {
    const double dx = x - viewpoint.x(), dy = y - viewpoint.y(), run = std::hypot(dx, dy);
    double slope = 0.0;
    if (!horizons.LowestBeyond(std::atan2(dy, dx), run + dem->cell_m, half, &slope)) return false;
    *height = viewpoint.z() + run * slope;
    return true;
  };
  const bool beyond_possible = std::isfinite(data_reach_m);
  const double shadow_reach = o.KrigingReach(data_reach_m);
  const int reach = static_cast<int>(
      std::ceil(beyond_possible ? std::max(o.edge_m, shadow_reach + 1.0) : o.edge_m));
  const int near_cells = static_cast<int>(std::ceil(o.near_m));
  // Rows in parallel: a cell reads and writes only its own height; each row keeps its counts,
  // summed in row order afterwards (the same result on any number of threads).
  struct RowCounts {
    int lowered = 0, in_object_shadows = 0, unexplained = 0;
    double lowering_m = 0.0;
  };
  std::vector<RowCounts> counts(static_cast<size_t>(dem->rows));
  cv::parallel_for_(cv::Range(0, dem->rows), [&](const cv::Range& rows) {
    for (int row = rows.start; row < rows.end; ++row)
      for (int col = 0; col < dem->cols; ++col) {
        RowCounts& count = counts[static_cast<size_t>(row)];
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
        // The nearest ground point (when it may lie beyond data_reach_m) and the directions to
        // the ground within edge_m, one per grid cell.
        std::vector<double> directions;
        double nearest = std::numeric_limits<double>::infinity();
        for (int r = r0 - reach; r <= r0 + reach; ++r)
          for (int c = c0 - reach; c <= c0 + reach; ++c) {
            if (!grid.Inside(c, r) || grid.Count(c, r) == 0) continue;
            if (beyond_possible)
              for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i)
                nearest = std::min(
                    nearest, std::hypot(ground_points[*i].x() - x, ground_points[*i].y() - y));
            const Eigen::Vector3d& p = ground_points[*grid.begin(c, r)];
            if (std::hypot(p.x() - x, p.y() - y) <= o.edge_m)
              directions.push_back(std::atan2(p.y() - y, p.x() - x));
          }
        double horizon = 0.0;
        Setter setter = Setter::kOther;
        const bool has_horizon = line_over(horizons, x, y, &horizon, &setter);
        if (nearest > data_reach_m) {
          double ground_horizon = 0.0;
          Setter ground_setter = Setter::kGround;
          const bool below_terrain_horizon =
              line_over(ground_horizons, x, y, &ground_horizon, &ground_setter) &&
              z < ground_horizon - o.tolerance_m;
          if (nearest <= shadow_reach && has_horizon && setter == Setter::kObject && z < horizon &&
              !below_terrain_horizon) {
            ++count.in_object_shadows;
          } else {
            z = Raster::kNoData;
            if (std) std->at(row, col) = Raster::kNoData;
            ++count.unexplained;
          }
          continue;
        }
        if (LargestAngularGap(std::move(directions)) <= M_PI) continue;
        // The bound: a line of sight that passed over the cell to farther ground, if any (seen
        // ground that went unmatched lies below it, above the horizon); else the horizon.
        double bound = horizon;
        if (!line_beyond(x, y, &bound) && (!has_horizon || setter == Setter::kObject)) continue;
        if (z <= bound + o.tolerance_m) continue;
        count.lowering_m += z - bound;
        // Lowered to the horizon on the premise that ground seen is ground matched: the kriged
        // height stays possible (seen, not matched), so the std spans it.
        if (std && !Raster::IsNoData(std->at(row, col)))
          std->at(row, col) = static_cast<float>(std::hypot(std->at(row, col), z - bound));
        z = static_cast<float>(bound);
        ++count.lowered;
      }
  });
  result.horizon = *dem;
  for (int row = 0; row < dem->rows; ++row)
    for (int col = 0; col < dem->cols; ++col) {
      float& h = result.horizon.at(row, col);
      if (!Raster::IsNoData(dem->at(row, col))) {
        h = Raster::kNoData;
        continue;
      }
      double height = 0.0;
      Setter setter = Setter::kOther;
      const bool found =
          line_over(horizons, dem->CellCentreX(col), dem->CellCentreY(row), &height, &setter);
      h = found && setter != Setter::kObject ? static_cast<float>(height) : Raster::kNoData;
    }
  double lowered = 0.0;
  for (const RowCounts& c : counts) {
    result.cells_lowered += c.lowered;
    result.cells_in_object_shadows += c.in_object_shadows;
    result.cells_unexplained += c.unexplained;
    lowered += c.lowering_m;
  }
  if (result.cells_lowered > 0) result.mean_lowering_m = lowered / result.cells_lowered;
  return result;
}

}  // namespace ts
