#pragma once
// The ground-truth directory of a simulated station (never inside the station directory):
//   dem.tif         bare earth, 1 m cells over the whole scene, frame L
//   dem_fine.tif    bare earth, 0.25 m cells
//   objects.tif     1 where a tree or bush covers the cell, 0 elsewhere (dem_fine's grid)
//   calibration.yaml  the true calibration, in the format `process --calibration` reads
//   truth.json      scene, seed, stage height h, sun, object counts and cover, rig errors;
//                   from `sim render` also the capture plan and the true encoder angles
//   range/pair_NN_{left,right}.tif  true range per pixel centre, float32 m, NaN for sky
//                   (`sim render --range`)
// Heights are point samples of exactly the rendered surface at the cell centres.
#include <nlohmann/json.hpp>
#include <string>

#include "core/result.h"
#include "processing/io/raster.h"
#include "sim/scene.h"
#include "sim/sim_rig.h"

namespace ts::sim {

// Bare-earth heights (or the object mask) sampled at the centres of cell_m cells covering
// the scene.
Raster SampleTerrain(const Scene& scene, double cell_m);
Raster SampleObjectMask(const Scene& scene, double cell_m);

// `extra` is merged into truth.json (e.g. the capture plan used).
Status WriteTruthDirectory(const Scene& scene, const SimRig& rig, const std::string& dir,
                           const nlohmann::json& extra = {});

}  // namespace ts::sim
