#pragma once
// What the lines of sight prove about the terrain (issue 22): every matched point was seen, so
// the terrain between its camera and it lies below that line. No DEM surface may stand above a
// line of sight that passed over it to farther ground: behind brows, dikes and trees alike,
// with no rule about which side the data lie on.
//
// A line counts up to end_sigmas standard deviations of its point's range short of the point
// (and at least a cell): its direction is known to a pixel, its length only to the
// intersection's range sigma, so a point matched too far would otherwise cut into the ground
// in front of it. A line is taken where it crosses the edges of the ceiling_cell_m squares:
// over a square the DEM's surface is all but straight along it, so there the line is lowest
// and nearest the surface. Per square two ceilings are kept (with where they were): the
// lowest line, and the one that passes least above the kriged DEM. Within a square the
// surface can rise more than the lines do (a steep cell beside a low one: a kriged blunder),
// and a line that is not the lowest then passes under it where it is high (0.5 m on terraces
// seed 2, when only the lowest was kept and the lines were taken every half square).
//
// The DEM is the bilinear surface of its cell centres. Each ceiling constrains the four cells
// around it: w'z <= h, w the bilinear weights. Each in turn is met by the least change of z
// (a projection onto its half-space). That only lowers cells, with weights that are never
// negative, so it cannot undo a constraint met before: one pass meets them all. It moves the
// cells unevenly, so the line that bound a square over the kriged DEM need not bind it over
// the lowered one: the lines that passed under the kriged DEM are walked again over the
// lowered one, and the closest under each square met, until none passes under it (a round or
// two). Cells the lines do not reach are untouched.
//
// Per cell, the lowest line over its square is also kept: the highest the ground of a cell
// can be (products/dem_ceiling.tif; ground_room.h caps the cells without data by it), and the
// height of the point it went to. Over ground hidden behind a brow, the lowest line grazes
// the brow and lands on the first ground seen past the hidden stretch (ground_room.h).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/io/raster.h"

namespace ts {

struct FreeSpaceOptions {
  bool enabled = true;
  double end_sigmas = 2.0;          // a line stops this many range sigmas short of its point
  double ceiling_cell_m = 0.25;     // per square this wide, the lowest line and the nearest bind
  double tolerance_m = 0.0;         // a surface this far above a line is left alone
  double seen_ground_sigmas = 3.0;  // a line this far under seen ground went through it
  int seen_ground_witnesses = 2;    // in at least this many squares
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("enabled", self.enabled, {"keep the DEM below every line of sight over it", "", 0, 1});
    v("end_sigmas", self.end_sigmas,
      {"a line of sight stops this many range sigmas short of its point", "", 0, 10});
    v("ceiling_cell_m", self.ceiling_cell_m,
      {"per square this wide, the lowest line of sight and the one nearest the DEM bind it", "m",
       0.05, 10});
    v("tolerance_m", self.tolerance_m,
      {"a surface this far above a line of sight is left alone", "m", 0, 10});
    v("seen_ground_sigmas", self.seen_ground_sigmas,
      {"a line of sight passing this many height sigmas (and a square's diagonal) under the "
       "ground points of a square went through seen ground",
       "", 0, 1000});
    v("seen_ground_witnesses", self.seen_ground_witnesses,
      {"squares of seen ground a line of sight must pass under to have gone through it", "", 1,
       1000});
  }
  bool Check(std::string* why) const;
};

// One seen point and the camera that saw it, in the DEM's frame.
struct SightLine {
  Eigen::Vector3d camera = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double range_sigma_m = 0.0;  // along the line
};

// The lowest lines of sight over the DEM's grid.
struct SightLineCeilings {
  struct Ceiling {
    double x = 0.0, y = 0.0, height = 0.0;
    double landing = 0.0;  // the height of the point the line went to
  };
  std::vector<Ceiling> ceilings;  // one per ceiling_cell_m square a line passed over
  Raster per_cell;                // the lowest line over each DEM cell's square (nodata: none)
  Raster landing_per_cell;        // where that lowest line landed: the first ground seen past
  // The lines that passed under the grid they were found over: LowerBelowSightLines walks them
  // again over the DEM it lowered.
  std::vector<SightLine> under_grid;
};

// grid: the kriged DEM, before any line lowered it.
SightLineCeilings FindSightLineCeilings(const std::vector<SightLine>& lines, const Raster& grid,
                                        const FreeSpaceOptions& options);

// A line of sight cannot pass under ground that was seen: its point was matched behind the
// surface in front of it (a repeated texture 20 m under a hill, badlands seed 5), however
// well it agrees with its few neighbours there. The seen ground of a ceiling_cell_m square is
// the second lowest ground point in it (one point alone may be a blunder itself); not the
// kriged ground, which bridges the hidden foot of a riser that the lines to the tread below
// rightly pass under. A line that passes under it by more than the square's diagonal (ground
// as steep as 45 degrees within the square) and seen_ground_sigmas of that point's height
// sigma, in seen_ground_witnesses squares or more before it stops short of its point (as in
// FindSightLineCeilings, at least min_gap_m), went through the ground. ground_variances_m2:
// one per ground point, or none. Per line, 1 where it went through seen ground.
std::vector<uint8_t> FindLinesThroughSeenGround(const std::vector<SightLine>& lines,
                                                const std::vector<Eigen::Vector3d>& ground,
                                                const std::vector<double>& ground_variances_m2,
                                                double min_gap_m, const FreeSpaceOptions& options);

struct FreeSpaceResult {
  int cells_lowered = 0;
  double max_lowering_m = 0.0;
  double mean_lowering_m = 0.0;
};

// Lowers `dem` (nodata cells stay) until its bilinear surface is below every ceiling whose
// four cells have data, and below the lines in ceilings.under_grid wherever they cross a
// square's edge (at most 8 rounds). A lowered cell's `std` (if given) spans its lowering in
// quadrature: the points kriged there stood above a line another point proved clear, by at least
// that much.
FreeSpaceResult LowerBelowSightLines(const SightLineCeilings& ceilings,
                                     const FreeSpaceOptions& options, Raster* dem,
                                     Raster* std = nullptr);

}  // namespace ts
