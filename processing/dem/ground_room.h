#pragma once
// How far the ground of a DEM cell may lie from the DEM, where kriging's own standard deviation
// does not know (issue 22: dem_std.tif honest everywhere it has a value). Kriging's sigma
// assumes the terrain's variogram holds everywhere; two things it cannot see:
//  - in a cell the cameras saw, ground that departs from the DEM's surface within the cell
//    (a riser, a ditch's edge, a gully's lip): the ground points there show it. Their mean
//    squared departure from the cubic surface through the cell centres (which follows curved
//    ground where the bilinear one cuts chords), less their own variance, is added.
//  - at a cell's centre d metres from the nearest ground point (or the mark): kriging's linear
//    drift carries the slope of the ground around on to it; ground hidden behind a brow or a
//    dike may turn away from that slope as much as the seen ground turns near it, by up to
//    t d with t the range of the seen cells' gradients within slope_window_m of the cell, or
//    within d where d is longer (farther out no seen cell is that near; the ground turns over
//    the whole reach). That room is taken as two standard deviations. It is what matters in cells
//    nobody saw (no ground point in them), and at the centre of a cell seen at one corner. A seen
//    cell whose centre has points all around it (no gap over 180 degrees among those within a cell
//    of its nearest) shows its own turns, in the departure above and in kriging's sigma: no room.
//    The lines of sight above (free_space.h) have already taken the DEM down to where the ground
//    can be.
//  - in a cell nobody saw behind a brow, or whose centre lies beyond the points it holds (a
//    terrace's lip in the cell, its lower tread at the centre), the room below: the lowest
//    line of sight over it grazed the brow and landed on the first ground seen past (a
//    terrace's lower tread, a dike's far field, a gully's far wall), and kriging bridged the
//    DEM across. The ground plausibly lies anywhere down to that landing; the RMS distance to
//    it is taken, if it exceeds the turn's room (the two bound the same unknown).
//  - in a cell no line of sight passed over, nothing bounds the ground from below, and the
//    seen ground near it need not say how it goes on: behind a brow the ground turns where
//    nobody sees (a terrace's riser past the last tread seen, a gully behind its crest). There
//    it may fall away as steeply as the ground this station saw does (the seen cells' slope at
//    steep_slope_quantile): anywhere down to that slope times the distance to the points, whose
//    RMS distance is taken if it exceeds the other rooms.
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/dem/cell_ground.h"
#include "processing/dem/free_space.h"
#include "processing/dem/kriging.h"
#include "processing/io/raster.h"

namespace ts {

struct GroundRoomOptions {
  bool enabled = true;
  double slope_window_m = 5.0;         // the seen slopes within this of a cell bound its turn
  double steep_slope_quantile = 0.95;  // of the seen slopes: how steeply unbounded ground falls
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("enabled", self.enabled, {"widen the std by what the ground could do", "", 0, 1});
    v("slope_window_m", self.slope_window_m,
      {"how much the seen slopes within this of a cell (at least) turn bounds its unseen ground",
       "m", 0, 100});
    v("steep_slope_quantile", self.steep_slope_quantile,
      {"the seen cells' slope at this quantile: how steeply ground no line of sight passed "
       "over may fall away",
       "", 0, 1});
  }
  bool Check(std::string* why) const;
};

struct GroundRoomResult {
  int seen_cells = 0, unseen_cells = 0;   // cells with data
  double median_unseen_widening_m = 0.0;  // the room's std in unseen cells
  double median_seen_departure_m = 0.0;   // the ground's departure in seen cells
};

// Every cell of the square for the terrain correction, also those without data: each gets the
// height of the nearest cell with data carried on along that cell's slope, capped by the lines
// of sight over it (the per-cell ceilings of free_space.h, or none) or, where none passes over
// it, by the horizon the terrain sets there (horizon_limit.h's, or none): a ridge's flank
// falls away behind its brow faster than the line of sight over it, or it would have been seen;
// the brow's slope carried on stands metres above it. The std is the room the seen ground's
// turn near that cell leaves over the distance, or below it down to the landing of the line
// over it, or with no line over it down the station's steep slope, as above.
struct GroundEstimate {
  Raster height, std;
  std::vector<CellGround> kind;  // per cell
};
GroundEstimate EstimateEveryCell(const KrigingPoints& ground, const Raster& dem, const Raster& std,
                                 const SightLineCeilings* sight, const Raster* horizon,
                                 const GroundRoomOptions& options);

// ground: the ground points kriged, in the DEM's frame; sight: the lines of sight over the
// DEM's grid (or none). Widens `std` (the DEM's grid) where `dem` has data.
GroundRoomResult WidenStdByGroundRoom(const KrigingPoints& ground, const Raster& dem,
                                      const SightLineCeilings* sight,
                                      const GroundRoomOptions& options, Raster* std);

}  // namespace ts
