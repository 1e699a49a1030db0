#pragma once
// The DEM of difference between two survey epochs (seed 002; the level of detection of
// Wheaton et al. 2010, Earth Surf. Process. Landforms 35:136): dz = after - before per cell
// on the grid of `before`, sigma = sqrt(std_before^2 + std_after^2), the cells whose change is
// significant, and what a deformation survey reports from them: areas and volumes of lowering
// and raising with their errors, the net volume, the deepest subsidence with its sigma and
// position, and the connected subsidence regions with their outlines.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/io/raster.h"

namespace ts {

struct DemEpoch {
  std::string name;  // the file, for messages
  Raster dem;
  std::optional<Raster> std_dev;  // standard deviation per cell, on the DEM's grid
};

struct ChangeOptions {
  double lod_m = 0.0;
  double t_critical = 1.96;  // 95 %, two-sided
  bool remove_stable_offset = false;
  double min_region_area_m2 = 4.0;
  // A region grows from its significant core into 4-neighbours lowered by at least
  // region_grow_t * sigma (hysteresis, as Canny's edges): a gentle bowl's rim, where no single
  // cell is significant, still belongs to it. Much below 1, noise cells join in numbers.
  double region_grow_t = 1.0;
  double basin_reach_m = 10.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("lod_m", self.lod_m,
      {"fixed level of detection (0: per-cell t-test from the std grids)", "m", 0, 99.999});
    v("t_critical", self.t_critical, {"t of the per-cell test", "", 0.01, 10});
    v("remove_stable_offset", self.remove_stable_offset,
      {"level the later epoch on the unchanged ground first (epochs not on one height datum)"});
    v("min_region_area_m2", self.min_region_area_m2,
      {"smallest subsidence region listed (smaller cores are counted)", "m2", 0, 1e9});
    v("region_grow_t", self.region_grow_t,
      {"a region grows into cells lowered by this many sigma (below 0.6 noise percolates)", "", 0.6,
       10});
    v("basin_reach_m", self.basin_reach_m,
      {"then ring by ring while a ring's mean lowering is significant, this far", "m", 0, 100});
  }
  bool Check(std::string* why) const;
};

// Significant cells of one sign. Volumes and their errors are positive magnitudes.
struct ChangeVolume {
  int cells = 0;
  double area_m2 = 0.0;
  double volume_m3 = 0.0;
  double sigma_m3 = 0.0;             // cell errors independent
  double sigma_correlated_m3 = 0.0;  // cell errors fully correlated: the upper bound
  // Adds a cell changed by `amount_m` in the volume's sense (a region's basin also sums cells
  // that noise moved the other way) with its sigma; sigma_m3 holds the variance until Finish().
  void AddCell(double amount_m, double sigma_m, double cell_area_m2);
  void Finish();
};

// One polygon of an outline, along cell edges in the grid's coordinates: its exterior ring and
// the rings of its holes, each closed (first point repeated last).
struct OutlinePolygon {
  std::vector<Eigen::Vector2d> exterior;
  std::vector<std::vector<Eigen::Vector2d>> holes;
};

// A connected (8-neighbour) area of significant lowering, grown into its rim.
struct SubsidenceRegion {
  int id = 0;                 // 1, 2, ... by volume, largest first
  ChangeVolume lowering;      // over the grown region
  int significant_cells = 0;  // its core
  double max_depth_m = 0.0;   // deepest cell, positive down
  double max_depth_sigma_m = 0.0;
  Eigen::Vector2d deepest_xy_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d centroid_xy_m = Eigen::Vector2d::Zero();  // depth-weighted
  std::vector<OutlinePolygon> outline;                      // as GDAL's polygonizer traces it
};

// The values of ChangeResult::change_class.
constexpr float kSignificantLowering = -1.0f;
constexpr float kBelowDetection = 0.0f;
constexpr float kSignificantRaising = 1.0f;

struct ChangeResult {
  Raster dod;                    // after - before, m; nodata where either epoch has none
  Raster dod_std;                // sigma of dz, m
  Raster change_class;           // k*Lowering/Detection/Raising per compared cell, nodata elsewhere
  bool after_resampled = false;  // `after` was on another grid: bilinear onto `before`'s
  bool sigma_from_lod = false;   // no std grids: sigma = lod / t_critical everywhere
  int cells_compared = 0;
  double area_compared_m2 = 0.0;
  double compared_fraction_before = 0.0;  // of the cells with data in each epoch
  double compared_fraction_after = 0.0;
  ChangeVolume lowering, raising;
  double net_volume_m3 = 0.0;  // raising - lowering, over the significant cells
  double net_sigma_m3 = 0.0;
  // The deepest significant lowering (positive down), if there is any.
  std::optional<double> max_subsidence_m;
  double max_subsidence_sigma_m = 0.0;
  Eigen::Vector2d max_subsidence_xy_m = Eigen::Vector2d::Zero();
  std::vector<SubsidenceRegion> regions;
  // The t a region's deepest cell must reach to be listed: t_critical's level over all the
  // compared cells at once, so that noise alone lists a region in at most that share of surveys.
  double region_deepest_t = 0.0;
  // Median dz over the cells below detection: ~0 unless the epochs' height datums differ.
  double stable_median_m = 0.0;
  double offset_removed_m = 0.0;  // subtracted from the later epoch (remove_stable_offset)
  std::vector<std::string> warnings;
};

// Errors (one line naming the epoch's file): different CRS, grids that do not overlap or share
// no cell with data, a std grid not on its DEM's grid, no std grid without a fixed LoD.
Result<ChangeResult> ComputeDemOfDifference(const DemEpoch& before, const DemEpoch& after,
                                            const ChangeOptions& options = {});

}  // namespace ts
