#pragma once
// Near-region terrain correction of a gravity reading from a DEM: the attraction of the
// terrain's departure from the Bouguer plate through the station mark, as the correction to
// add to the reading (mGal). Every cell is a vertical prism between the terrain and the mark's
// height H, evaluated exactly (prism.h) at the gravimeter's sensor, H + sensor height above
// the mark:
//   TC = sum over cells of  g_down(missing mass, terrain below H)  -  g_down(excess, above H)
// so terrain above and below the station both raise the correction (a bump below the sensor
// lowers it, as it must).
//
// The innermost cells decide the answer: a staircase of flat-topped 1 m prisms overestimates
// a sloping surface at the station by tens of percent. Cells within refine_radius_m are cut
// into a quadtree of sub-prisms, finer towards the station, with heights interpolated
// bilinearly, and the surface there is tied to the station mark (a known ground point): the
// DEM's misfit at the mark is removed, tapering to nothing at refine_radius_m.
//
// Uncertainty: per cell, the standard deviation of its prism's correction when its height is
// normal about the DEM's with the cell's standard deviation (three-point Gauss-Hermite over
// the exact prism), cells taken as independent (kriging errors of neighbouring cells are
// correlated: the value is a lower bound; the fully correlated bound, the sum of the cells'
// sigmas, is reported beside it). Not the slope dTC/dh times the std: a column's correction
// grows with the square of its height difference from the mark, so ground at the mark's
// height with a std of metres would get no sigma at all, yet it could add as much as ground
// metres higher or lower does.
// Cells whose ground nobody saw (given as such) are the exception: how hidden ground goes is one
// unknown for all of them (the ground behind a dike is all lower, or all not), so their
// contributions add linearly, and that sum adds to the independent sigma in quadrature.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/dem/cell_ground.h"
#include "processing/gravity/prism.h"
#include "processing/io/raster.h"

namespace ts {

struct TerrainCorrectionOptions {
  double density_kg_m3 = kStandardDensityKgM3;
  double sensor_height_m = 0.0;  // gravimeter sensor above the station mark
  double radius_m = 0.0;         // cells whose centre is within it; 0: the whole DEM
  double refine_radius_m = 6.0;
  // Refined cells are split into quarters while a square's side exceeds refine_ratio times
  // its distance from the station (down to min_subcell_m).
  double refine_ratio = 0.2;
  double min_subcell_m = 0.005;
  // Columns at least this many sides from the sensor are vertical line masses (prism.h's far
  // field, relative error < 1e-4 there); 0: the exact prism everywhere.
  double far_field_ratio = 5.0;
  double min_ring_coverage = 0.9;  // warn below
  // Below these shares of cells with data within 10 m and within 30 m of the mark, the
  // correction is unusable: estimated from so little seen ground, its sigma would claim what
  // nobody measured (a survey with a lens 1e6 off gave 7 points and 0.038 +- 0.28 mGal).
  double min_coverage_10m = 0.5;
  double min_coverage_30m = 0.3;
  // And below this share of cells within 30 m that the cameras saw (ground points in them;
  // only where the DEM says which were seen): kriging reaches 5 m from a point, so 30 points
  // of an overexposed capture gave a DEM over 38 % of the square and a std 4 times too small.
  double min_seen_30m = 0.1;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("density_kg_m3", self.density_kg_m3, {"density of the terrain", "kg/m3", 100, 10000});
    v("sensor_height_m", self.sensor_height_m,
      {"gravimeter sensor above the station mark", "m", 0, 100});
    v("radius_m", self.radius_m,
      {"cells whose centre is within it (0: the whole DEM)", "m", 0, 100000});
    v("refine_radius_m", self.refine_radius_m,
      {"prisms within this are refined towards the station", "m", 0, 1000});
    v("refine_ratio", self.refine_ratio, {"sub-prism size over distance", "", 0.001, 10});
    v("min_subcell_m", self.min_subcell_m, {"smallest sub-prism", "m", 0.0001, 10});
    v("far_field_ratio", self.far_field_ratio,
      {"distance over size beyond which a prism is a point mass (0: exact)", "", 0, 1000});
    v("min_ring_coverage", self.min_ring_coverage, {"warn when a ring is covered less", "", 0, 1});
    v("min_coverage_10m", self.min_coverage_10m,
      {"unusable when less of the ground within 10 m has data", "", 0, 1});
    v("min_coverage_30m", self.min_coverage_30m,
      {"unusable when less of the ground within 30 m has data", "", 0, 1});
    v("min_seen_30m", self.min_seen_30m,
      {"unusable when less of the ground within 30 m was seen", "", 0, 1});
  }
  bool Check(std::string* why) const;
};

// A ring's cells in one direction: which way to look again when the ring is thin.
struct SectorContribution {
  double bearing_deg = 0.0;  // centre, clockwise from the frame's +Y (pan 0 in frame L)
  double coverage = 0.0;     // share of its cells with data
  double seen = 0.0;         // share of its cells seen (a ground point in them)
  double sigma_mgal = 0.0;   // its seen and unseen parts together, as the ring's
};

struct RingContribution {
  double inner_m = 0.0, outer_m = 0.0;  // outer = infinity for "the rest of the DEM"
  double mgal = 0.0;
  double coverage = 0.0;           // share of the ring's cells with data
  double sigma_mgal = 0.0;         // the ring's own sigma (its seen and unseen parts together)
  double sigma_unseen_mgal = 0.0;  // of it, from ground nobody saw
  std::vector<SectorContribution> sectors;  // kSectors of them, bearings 0, 30, ... 330 deg
};

// As many sectors as the capture plan has poses per row, centred on their pans.
constexpr int kSectors = 12;

struct TerrainCorrection {
  double total_mgal = 0.0;
  double sigma_mgal = 0.0;                 // seen cells independent, unseen ones as one
  double sigma_unseen_mgal = 0.0;          // of it, from ground nobody saw
  double sigma_correlated_mgal = 0.0;      // every cell fully correlated (upper bound)
  std::vector<RingContribution> rings;     // 0-2, 2-10, 10-20, 20-30, 30-50 m, rest
  double quadrant_mgal[4] = {0, 0, 0, 0};  // NE, SE, SW, NW (x east, y north)
  double station_misfit_m = 0.0;           // DEM at the mark minus the mark's height (removed)
  std::vector<std::string> warnings;
  std::string unusable_because;  // empty: usable; else why the correction means nothing
  bool Usable() const { return unusable_because.empty(); }
};

// station_mark: (x, y, z) of the mark in the DEM's frame. dem_std may be null (sigma 0).
// ground: one per cell, or null (every cell with data seen); kEstimated cells have a height
// that is not the DEM's (they count as without data in the rings' coverage).
TerrainCorrection ComputeTerrainCorrection(const Raster& dem, const Raster* dem_std,
                                           const Eigen::Vector3d& station_mark,
                                           const TerrainCorrectionOptions& options,
                                           const std::vector<CellGround>* ground = nullptr);

}  // namespace ts
