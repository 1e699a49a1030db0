#pragma once
// terrain_correction.json: the correction with its standard deviation, contributions by ring
// and quadrant, ring coverage and warnings, and what it was computed from.
#include <nlohmann/json.hpp>

#include "processing/gravity/terrain_correction.h"

namespace ts {

nlohmann::json TerrainCorrectionToJson(const TerrainCorrection& tc,
                                       const TerrainCorrectionOptions& options,
                                       const Eigen::Vector3d& station_mark);

}  // namespace ts
