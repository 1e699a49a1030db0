#pragma once
// products/report.json, built from the steps' summaries: what ran, how long, what it counted
// and warned, the DEM and its variogram, the terrain correction, the accuracy the rig can
// reach, and what is needed to reproduce it (software version, options, the calibration's
// source and checksum).
#include <nlohmann/json.hpp>

#include "processing/pipeline/station_steps.h"

namespace ts {

nlohmann::json BuildProcessReport(const ProcessOptions& options, const StationWork& work,
                                  const ProcessSummary& summary, double wall_s);

}  // namespace ts
