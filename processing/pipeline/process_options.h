#pragma once
// The options of `process`: the DEM's geometry and each step's options, with the values a
// tripod's station wants where they differ from a step's own defaults (the presets named
// beside each step's options).
#include <nlohmann/json.hpp>
#include <string>

#include "core/options.h"

#include "processing/calibration/rig_adjustment.h"
#include "processing/calibration/rig_tie_points.h"
#include "processing/cloud/ground_filter.h"
#include "processing/cloud/height_blunder_filter.h"
#include "processing/cloud/sight_line_objects.h"
#include "processing/cloud/underside_patches.h"
#include "processing/dem/free_space.h"
#include "processing/dem/ground_room.h"
#include "processing/dem/horizon_limit.h"
#include "processing/dem/kriging.h"
#include "processing/gravity/terrain_correction.h"
#include "processing/matching/pair_matcher.h"
#include "processing/products/panorama.h"

namespace ts {

struct ProcessOptions {
  std::string calibration_file;  // empty: the calibration recorded in station.json
  // The calibration file was written for this station: its levelling and height too.
  bool set_up_from_calibration_file = false;
  std::string gcp_file;           // empty: the DEM stays in the station frame L
  double dem_half_size_m = 30.0;  // the DEM covers the square of 2 x this around the station
  double dem_cell_m = 1.0;
  double cloud_margin_m = 10.0;     // points this far beyond the square still inform the DEM
  bool self_calibrate_rig = false;  // go on with the stage adjusted on the station's own seams
  RigTiePointOptions rig_ties;
  RigAdjustmentOptions rig_adjustment;
  PairMatchOptions matching = PairMatchOptions::ForStation();
  HeightBlunderOptions blunders;
  SightLineOptions sight_lines;
  GroundFilterOptions ground = GroundFilterOptions::ForTripod();
  UndersidePatchOptions underside_patches;
  KrigingOptions kriging;
  HorizonLimitOptions horizon;
  FreeSpaceOptions free_space;
  GroundRoomOptions ground_room;
  PanoramaOptions panorama;
  TerrainCorrectionOptions terrain_correction;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("calibration_file", self.calibration_file, {"calibration YAML (empty: station.json's)"});
    v("set_up_from_calibration_file", self.set_up_from_calibration_file,
      {"the calibration file was written for this station: take its levelling and height above "
       "the mark too (else station.json's)"});
    v("gcp_file", self.gcp_file, {"ground control points YAML (empty: the station frame L)"});
    v("dem_half_size_m", self.dem_half_size_m, {"the DEM square's half side", "m", 5, 500});
    v("dem_cell_m", self.dem_cell_m, {"DEM cell size", "m", 0.1, 10});
    v("cloud_margin_m", self.cloud_margin_m,
      {"points this far beyond the square still inform the DEM", "m", 0, 100});
    v("self_calibrate_rig", self.self_calibrate_rig,
      {"refine the stage kinematics on the station's own panorama"});
    v.Group("rig_ties", self.rig_ties);
    v.Group("rig_adjustment", self.rig_adjustment);
    v.Group("matching", self.matching);
    v.Group("blunders", self.blunders);
    v.Group("sight_lines", self.sight_lines);
    v.Group("ground", self.ground);
    v.Group("underside_patches", self.underside_patches);
    v.Group("kriging", self.kriging);
    v.Group("horizon", self.horizon);
    v.Group("free_space", self.free_space);
    v.Group("ground_room", self.ground_room);
    v.Group("panorama", self.panorama);
    v.Group("terrain_correction", self.terrain_correction);
  }
  // Every field in its range, and each step's own consistency checks.
  bool Check(std::string* why) const;
};

nlohmann::json ProcessOptionsToJson(const ProcessOptions& options);

}  // namespace ts
