#pragma once
// A retake (issue 25): poses of a captured station to take again, because the verdict found a
// direction the DEM lacks (a passer-by, a vehicle, a dark pair). Their pairs' images are moved
// to retaken/UTC/ (kept, never deleted) and their records dropped from the manifest, so that a
// resumed capture takes exactly those poses again; a pose the plan does not have is added to
// it. Crash-safe in either order: a record whose images are gone is retaken by resume.
#include <string>
#include <vector>

#include "core/result.h"
#include "core/stage_pose.h"

namespace ts {

struct RetakeSummary {
  int set_aside = 0;   // pairs whose images moved to retaken/
  int added = 0;       // poses added to the plan
  std::string folder;  // retaken/UTC, relative to the station
};

// A pose matches a planned one within tolerance_deg on both axes.
Result<RetakeSummary> SetPairsAsideForRetake(const std::string& station_dir,
                                             const std::vector<StagePose>& poses,
                                             double tolerance_deg = 0.05);

}  // namespace ts
