#pragma once
// A child process whose output goes to a log file: for commands that run other topostation
// commands as a field team would (survey --sim's calibration session, the daemon's
// calibrate_rig jobs), so that a failure in them takes nothing of the caller with it.
#include <sys/types.h>

#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

// Starts args[0] with `args` (args[0] included), its stdout and stderr to `log` (truncated).
Result<pid_t> SpawnWithLog(std::vector<std::string> args, const std::string& log);

}  // namespace ts
