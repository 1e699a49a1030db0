#pragma once
// The headless unit on a tripod: a survey once the rig is ready after the daemon starts
// (mode when_ready), or one every N hours (mode schedule, a subsidence site watched over
// time). Each is an ordinary job, with a station id from the configured pattern; a survey due
// while the rig is busy or not ready waits for the next tick.
#include <chrono>
#include <string>

#include "station/daemon/daemon_config.h"
#include "station/daemon/device_supervisor.h"
#include "station/daemon/job_runner.h"

namespace ts::daemon {

class HeadlessScheduler {
 public:
  using Clock = std::chrono::steady_clock;
  HeadlessScheduler(const DaemonConfig& config, DeviceSupervisor* devices, JobRunner* jobs)
      : config_(config), devices_(devices), jobs_(jobs) {}
  // Called about once a second.
  void Tick(Clock::time_point now = Clock::now());

 private:
  bool Due(Clock::time_point now) const;
  const DaemonConfig& config_;
  DeviceSupervisor* devices_;
  JobRunner* jobs_;
  bool started_once_ = false;
  Clock::time_point last_start_{};
};

}  // namespace ts::daemon
