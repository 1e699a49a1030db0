#pragma once
// `process`: a captured station directory to its products (DESIGN.md "Processing pipeline"):
//   load (manifest, calibration, GCPs) -> matching and intersection into L, pair by pair ->
//   median-height blunder filter -> objects along the lines of sight -> ground filter ->
//   underside patches -> kriging at 1 m over the square around the station (optionally
//   georeferenced with GCPs) -> cells nobody saw bounded by what hid them (horizon_limit.h) ->
//   terrain correction -> products/ (points.ply, dem.tif, dem_std.tif, dem.png, panorama.png,
//   terrain_correction.json) -> report.json, written last.
// The steps are station_steps.h; StationProcessor (station_processor.h) runs them, pair by pair
// during a capture or all at once on a finished station; ProcessStation is the latter.
#include "processing/pipeline/process_options.h"
#include "processing/pipeline/station_processor.h"
