#pragma once
// topostationd: the parts wired together. The device supervisor, the job runner and the HTTP
// API; the headless modes (a survey as soon as the rig is ready, or on a schedule), each an
// ordinary job in the history; systemd's notifications (READY, STATUS with the current job,
// a watchdog fed only while the device poll goes round).
#include <atomic>
#include <string>

#include "core/result.h"
#include "station/daemon/daemon_config.h"

namespace ts::daemon {

// Runs until `stop` becomes true (SIGTERM, SIGINT). An error when it cannot start (config,
// token, job history, the listen address).
Status RunDaemon(const DaemonConfig& config, const std::atomic<bool>& stop);

}  // namespace ts::daemon
