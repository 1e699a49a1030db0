#pragma once
// Cells nobody saw, bounded by what hid them.
//
// Ground hidden behind a brow lies below the horizon. A tripod sees the terrain up to a brow and
// then, over it, farther ground or nothing; the hollow behind the brow is hidden because it
// falls away faster than the line of sight over the brow. Kriging extrapolates the slope
// before the brow into the hollow (up to KrigingOptions::max_distance_m), above where the
// ground can be: had it been there, the station would have seen it.
//
// So a DEM cell that was not seen (no ground point within near_m) and lies beyond the edge of
// the seen ground (the ground points within edge_m all on one side of it: an angular gap over
// 180 degrees, as one or two of them always are) is lowered to its bound when it stands above
// it by more than tolerance_m. Where something was seen beyond the cell (a point a cell or more
// farther, within +-bin_half_width_deg of its azimuth), the bound is the lowest line of sight to
// it: that line passed over the cell, and ground seen there and not matched lies between it and
// the horizon. Where nothing was, the bound is the horizon: the highest line of sight, from the
// viewpoint, to a point in front of the cell (nearer than it, in the same azimuths). A horizon
// set by an object (a point standing min_object_height_m above the DEM) does not count: ground
// hidden behind a tree continues the ground around it and may rise above the line of sight
// over the tree's lowest seen part. One set by a point on the terrain counts, ground or not:
// the crest of a dike or an embankment is convex ground the ground filter often leaves out,
// and it is what hides the hollow behind. Cells between seen ground and cells with ground near
// them are left to kriging.
//
// Ground hidden by an object is the other case: a bush or a grove hides ground that goes on
// beneath and behind it, at the level of the ground around it, so kriging may reach farther
// there (object_shadow_reach_m) than where nothing explains the gap (data_reach_m, kriging's own
// reach). A cell farther than data_reach_m from any ground point keeps its kriged height only
// when it lies within object_shadow_reach_m of ground, its horizon is set by an object point
// (one standing min_object_height_m or more above the DEM) and passes above the cell, and the
// ground's own horizon does not (by more than tolerance_m): the object alone hid it. Every other
// such cell becomes nodata. Its kriging standard deviation says how far it reached.
//
// The horizon comes from the points that were matched: where seen ground went unmatched it
// lies too low, which is why only extrapolated cells are lowered, why a line to farther ground
// comes first, and why a lowered cell's std (when given) spans the height it was lowered from:
// ground seen and not matched stands there.
//
// The cells the DEM is left without get their horizon too (HorizonLimitResult::horizon): the
// terrain correction estimates every cell of the square, and ground nobody saw behind a brow
// lies below it (ground_room.h's EstimateEveryCell, where no line of sight crosses the cell).
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/io/raster.h"

namespace ts {

struct HorizonLimitOptions {
  bool enabled = true;
  double near_m = 1.0;              // a ground point this close: the cell was seen
  double edge_m = 8.0;              // the ground this close decides "beyond the edge"
  double bin_half_width_deg = 1.0;  // the lines of sight that make a cell's horizon
  double tolerance_m = 0.2;         // above the horizon by more than this: lowered
  // Kriging's reach in the shadow of an object (see above); at most data_reach_m: none.
  // Only there: where nothing explains a gap (hollows behind brows), a longer reach bridges
  // ground that is not there.
  double object_shadow_reach_m = 7.0;
  // An object point stands this far above the DEM at least (lower ones are terrain that the
  // ground filter left out, at brows and rough ground).
  double min_object_height_m = 0.5;
  // How far kriging must reach for this stage, given kriging's own reach (data_reach_m).
  double KrigingReach(double data_reach_m) const {
    return enabled ? std::max(data_reach_m, object_shadow_reach_m) : data_reach_m;
  }
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("enabled", self.enabled, {"bound cells nobody saw by what hid them", "", 0, 1});
    v("near_m", self.near_m, {"a ground point this close: the cell was seen", "m", 0.01, 50});
    v("edge_m", self.edge_m, {"the ground this close decides beyond the edge", "m", 0.01, 100});
    v("bin_half_width_deg", self.bin_half_width_deg,
      {"azimuth half-width of the lines of sight of a cell's horizon", "deg", 0.001, 10});
    v("tolerance_m", self.tolerance_m,
      {"above the horizon by more than this: lowered", "m", 0, 10});
    v("object_shadow_reach_m", self.object_shadow_reach_m,
      {"kriging's reach in the shadow of a tree or bush", "m", 0, 50});
    v("min_object_height_m", self.min_object_height_m,
      {"an object stands this far above the DEM at least", "m", 0.01, 50});
  }
  bool Check(std::string* why) const;
};

struct HorizonLimitResult {
  int cells_lowered = 0;
  double mean_lowering_m = 0.0;
  int cells_in_object_shadows = 0;  // kept beyond data_reach_m
  int cells_unexplained = 0;        // beyond data_reach_m and not in an object's shadow: nodata
  // Over each cell the DEM is left without a value, the horizon the terrain sets there (the
  // DEM's grid; nodata where no line of sight reaches that far, or an object set it): ground
  // nobody saw lies below it, unless it was seen and not matched, which a line of sight over
  // the cell to farther ground would show (free_space.h).
  Raster horizon;
};

// points: the points seen from `viewpoint` (blunders left out), in the DEM's frame; ground: one
// flag per point (1 = ground). Lowers cells of `dem` (nodata cells are left alone) and sets
// cells farther than data_reach_m from ground that no object hides to nodata, in `std` too
// when given (the same grid).
HorizonLimitResult LimitToHorizon(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<uint8_t>& ground,
                                  const Eigen::Vector3d& viewpoint,
                                  const HorizonLimitOptions& options, Raster* dem,
                                  Raster* std = nullptr,
                                  double data_reach_m = std::numeric_limits<double>::infinity());

}  // namespace ts
