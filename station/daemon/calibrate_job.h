#pragma once
// A calibrate job: `topostation calibrate rig` (issue 21) on stations the daemon keeps, run as
// a child process beside the daemon's own binary, so that an adjustment that fails or is
// cancelled (killed) takes nothing of the daemon with it. The stage kinematics it estimates
// are written to a calibration file of the job's own; the rig config is not changed.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"
#include "processing/geometry/calibration.h"

namespace ts::daemon {

// `topostation calibrate rig DIRS... --calibration (start) --out out_yaml --json`, with
// --refine-cameras when asked; its JSON report, or the error with the last line it wrote.
// `should_stop` is asked every 100 ms.
Result<nlohmann::json> CalibrateRigInChild(const std::vector<std::string>& station_dirs,
                                           const Calibration& start, bool refine_cameras,
                                           const std::string& out_yaml,
                                           const std::function<bool()>& should_stop);

}  // namespace ts::daemon
