#pragma once
// The product files of a processed station (DESIGN.md "Station directory"), each written
// atomically into STATION/products/: points.ply, dem.tif, dem_std.tif, terrain_correction.json,
// dem.png, panorama.png. report.json is written apart, last (process_report.h).
#include "processing/pipeline/station_steps.h"

namespace ts {

bool WriteProducts(const ProcessOptions& o, const StationWork& w, StepSummary* s);

}  // namespace ts
