#pragma once
// `process`: a captured station directory to its products (DESIGN.md "Processing pipeline"):
//   load + check the raw pairs -> matching and intersection into L (all pairs) -> median-
//   height blunder filter -> objects along the lines of sight -> ground filter -> kriging at 1 m
//   over the square around the station (optionally georeferenced with GCPs) -> cells nobody saw
//   bounded by what hid them (horizon_limit.h) -> products/:
//   points.ply, dem.tif, dem_std.tif, dem.png, panorama.png, terrain_correction.json,
//   report.json.
// Every product is written atomically; report.json is written last.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "processing/cloud/ground_filter.h"
#include "processing/cloud/height_blunder_filter.h"
#include "processing/cloud/point_cloud.h"
#include "processing/cloud/sight_line_objects.h"
#include "processing/cloud/underside_patches.h"
#include "processing/common/result.h"
#include "processing/dem/horizon_limit.h"
#include "processing/dem/kriging.h"
#include "processing/gravity/terrain_correction.h"
#include "processing/io/raster.h"
#include "processing/matching/pair_matcher.h"
#include "processing/products/panorama.h"

namespace ts {

struct ProcessOptions {
  std::string calibration_file;   // empty: the calibration recorded in station.json
  std::string gcp_file;           // empty: the DEM stays in the station frame L
  double dem_half_size_m = 30.0;  // the DEM covers the square of 2 x this around the station
  double dem_cell_m = 1.0;
  double cloud_margin_m = 10.0;  // points this far beyond the square still inform the DEM
  // Points at least 20 cm apart on the ground: plenty for a 1 m DEM (kriging thins to
  // 25 cm), and a fraction of the near-tripod points the image-space grid gives. Measured
  // (simulator, 2 cores) 0.1 / 0.2 / 0.25 m: hills RMSE 0.174 / 0.174 / 0.174 m, coverage
  // within 30 m 95.1 / 95.1 / 94.9 %, processing 0.8 s and 1.1 s faster than at 0.1.
  // Least-squares windows of 17 x 17 instead of 21 x 21: the DEM averages dozens of points a
  // cell, so a point's precision matters less than their number and the time. Measured
  // (simulator, 2 cores; half window 10 / 8 / 7): hills RMSE 0.180 / 0.179 / 0.174 m,
  // coverage within 30 m 95.2 / 95.4 / 95.1 %, of the square 94.6 / 94.7 / 93.2 %; forest
  // 0.458 / 0.454 / 0.479 m; slope 0.100 / 0.097 m; process 3.60 / 3.11 / 3.01 s (hills).
  // With the row-only fit (half window 8, sigma <= 0.075 px; 10, 0.06): hills RMSE 0.173 /
  // 0.160 m, coverage within 30 m 95.2 / 94.8 %, process 2.5 / 2.7 s.
  PairMatchOptions matching = [] {
    PairMatchOptions m;
    m.min_spacing_m = 0.2;
    m.lsm.half_window_px = 8;
    m.lsm.max_sigma_px = 0.075;  // smaller windows, larger sigmas
    m.far_lsm.max_sigma_px = 0.075;
    m.near_lsm.max_sigma_px = 0.075;  // the same windows as lsm: 17 x 17
    return m;
  }();
  HeightBlunderOptions blunders;
  SightLineOptions sight_lines;
  // The ground filter tuned for a tripod's cloud (measured on the simulated forest: object
  // points > 0.5 m removed 87 % with the airborne defaults, 98.5 % with these; hills and flat
  // unchanged): a tighter band around the ground and a smaller slope allowance (the near
  // ground is dense and precise). Opening slope 0.15 / 0.10 / 0.08 at 20 cm point spacing:
  // forest objects removed 97.6 / 98.0 / 98.2 %, forest RMSE 0.52 / 0.47 / 0.47 m, hills and
  // slope within 5 mm.
  GroundFilterOptions ground = [] {
    GroundFilterOptions g;
    g.elevation_threshold_m = 0.2;
    g.elevation_scaler = 0.25;
    g.slope = 0.08;
    return g;
  }();
  UndersidePatchOptions underside_patches;
  KrigingOptions kriging;
  HorizonLimitOptions horizon;
  PanoramaOptions panorama;
  TerrainCorrectionOptions terrain_correction;
  // Called at the start of every stage with its name (from the calling thread).
  std::function<void(const std::string& stage)> progress;
  bool Check(std::string* why) const;
};

// What `process` made, beside the files: for callers that look further (benchmarks, tests).
enum PointClass : uint8_t { kOutsideDem = 0, kBlunder = 1, kObject = 2, kGround = 3 };
struct ProcessResult {
  nlohmann::json report;             // as written to products/report.json
  PointCloud cloud;                  // every intersected point, in L
  std::vector<uint8_t> point_class;  // PointClass per point of the cloud
  Raster dem, dem_std;
  TerrainCorrection terrain_correction;
};

// The products on success; an error naming the file and field otherwise.
Result<ProcessResult> ProcessStation(const std::string& station_dir, const ProcessOptions& options);

}  // namespace ts
