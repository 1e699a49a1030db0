#pragma once
// What `topostation diff` writes, for the CLI and the daemon's page alike: dod.tif,
// dod_std.tif, dod.png, subsidence.geojson and change.json in out_dir, from two processed
// stations or DEM GeoTIFFs.
#include <nlohmann/json.hpp>
#include <string>

#include "processing/change/dem_of_difference.h"

namespace ts {

struct DiffProducts {
  ChangeResult change;
  nlohmann::json json;  // as written to change.json
};

// truth_dir: the simulator's truth of the later epoch (its subsidence bowls), or empty.
// Throws CommandError naming the file at fault.
DiffProducts WriteDiffProducts(const std::string& before, const std::string& after,
                               const std::string& out_dir, const ChangeOptions& options,
                               const std::string& truth_dir = "");

}  // namespace ts
