#pragma once
// The options that describe a simulated station, shared by `sim render`, `sim serve` and
// `survey --sim`: scene or DEM, seed, stage height, and what changed at a later epoch.
#include <CLI/CLI.hpp>

#include "sim/sim_station.h"

namespace ts {

void AddSimStationOptions(CLI::App* cmd, sim::SimStationOptions* options);

}  // namespace ts
