#include "station/daemon/headless.h"

#include "core/log.h"

namespace ts::daemon {

bool HeadlessScheduler::Due(Clock::time_point now) const {
  switch (config_.headless.mode) {
    case HeadlessMode::kOff:
      return false;
    case HeadlessMode::kWhenReady:
      return !started_once_;
    case HeadlessMode::kSchedule:
      return !started_once_ || now - last_start_ >= std::chrono::duration<double, std::ratio<3600>>(
                                                        config_.headless.every_hours);
  }
  return false;
}

void HeadlessScheduler::Tick(Clock::time_point now) {
  if (!Due(now) || !devices_->WhyNotReady().empty() || !jobs_->CurrentJob().is_null()) return;
  const Result<std::string> station =
      NextStationId(config_.headless.station_pattern, config_.stations_dir);
  if (!station) {
    Log().error("headless: {}", station.error());
    started_once_ = true;
    last_start_ = now;
    return;
  }
  JobRequest request;
  request.kind = JobKind::kSurvey;
  request.station = *station;
  request.instrument_height_m = config_.headless.instrument_height_m;
  request.fields = {{"station", *station},
                    {"instrument_height_m", config_.headless.instrument_height_m},
                    {"line", config_.headless.line},
                    {"operator", "headless"},
                    {"notes", config_.headless.mode == HeadlessMode::kSchedule
                                  ? "headless: on schedule"
                                  : "headless: when the rig was ready"}};
  bool existed = false;
  const auto r = jobs_->Submit(request, "", &existed);
  if (const JobError* e = std::get_if<JobError>(&r)) {
    Log().warn("headless: survey of {} not started: {}", *station, e->message);
    return;  // tried again at the next tick
  }
  Log().info("headless: survey of {} started (job {})", *station, std::get<Job>(r).id);
  started_once_ = true;
  last_start_ = now;
}

}  // namespace ts::daemon
