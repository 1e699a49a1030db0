#pragma once
// The DEM a command works on, given as a processed station directory (products/dem.tif,
// products/dem_std.tif, the station mark from products/report.json) or as a bare GeoTIFF
// X.tif (its standard deviation from X_std.tif beside it, as `process` names them).
#include <Eigen/Core>
#include <optional>
#include <string>

#include "processing/io/raster.h"

namespace ts {

struct DemInput {
  bool station_dir = false;
  std::string dem_file;
  Raster dem;
  std::string std_file;  // empty when there is none
  std::optional<Raster> std_dev;
  std::optional<Eigen::Vector3d> station_mark;  // station directories only
};

// Heights no ground on Earth has: a DEM cell or a station mark beyond them is refused.
inline constexpr float kHighestGroundM = 9000.0f, kLowestGroundM = -11000.0f;

// Throws CommandError naming the file at fault (also for a cell beyond the heights above).
DemInput LoadDemInput(const std::string& input);

}  // namespace ts
