#include "station/daemon/daemon.h"

#include <systemd/sd-daemon.h>

#include <spdlog/sinks/base_sink.h>

#include <thread>

#include "core/log.h"
#include "devices/usb_watcher.h"
#include "station/daemon/access_token.h"
#include "station/daemon/device_supervisor.h"
#include "station/daemon/event_hub.h"
#include "station/daemon/headless.h"
#include "station/daemon/http_api.h"
#include "station/daemon/job_runner.h"
#include "station/daemon/job_store.h"

namespace ts::daemon {
namespace {

// The log's lines (warnings and errors of every job and device) as "log" events.
class EventLogSink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit EventLogSink(EventHub* hub) : hub_(hub) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    hub_->Publish("log", {{"level", spdlog::level::to_string_view(msg.level).data()},
                          {"message", std::string(msg.payload.data(), msg.payload.size())}});
  }
  void flush_() override {}

 private:
  EventHub* hub_;
};

// Removes the sink from the program's log when the daemon's parts go.
class SinkGuard {
 public:
  explicit SinkGuard(std::shared_ptr<spdlog::sinks::sink> sink) : sink_(std::move(sink)) {
    Log().sinks().push_back(sink_);
  }
  ~SinkGuard() {
    auto& sinks = Log().sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
  }

 private:
  std::shared_ptr<spdlog::sinks::sink> sink_;
};

std::string SystemdStatus(const nlohmann::json& job, const std::string& not_ready) {
  if (!job.is_null())
    return "job " + std::to_string(job.value("id", 0)) + ": " + job.value("kind", "") + " of " +
           job.value("station", "") + ", " + job.value("state", "");
  return not_ready.empty() ? "idle, rig ready" : "idle, " + not_ready;
}

// The USB devices the config names, watched by libusb hotplug; nullptr when none is named (or
// libusb cannot watch, which the log says).
std::unique_ptr<UsbWatcher> WatchUsb(const DaemonConfig& config, DeviceSupervisor* devices) {
  if (config.usb.empty()) return nullptr;
  std::vector<UsbMatch> matches;
  for (const auto& [name, id] : config.usb) matches.push_back(*ParseUsbMatch(name, id));
  auto watcher = UsbWatcher::Start(matches, [devices, &config](const UsbEvent& e) {
    devices->SetUsbPresence(e.name, config.usb.at(e.name), e.arrived);
  });
  if (!watcher) {
    Log().error("USB presence not watched: {}", watcher.error());
    return nullptr;
  }
  for (const auto& [name, id] : config.usb)
    devices->SetUsbPresence(name, id, (*watcher)->Present(name));
  return std::move(*watcher);
}

}  // namespace

Status RunDaemon(const DaemonConfig& config, const std::atomic<bool>& stop) {
  const Result<std::string> token = LoadOrCreateToken(config.token_file);
  if (!token) return Error{token.error()};
  const Result<RigConfig> rig = LoadRigConfig(config.rig_file);
  if (!rig) return Error{rig.error()};
  auto store = JobStore::Open(config.JobDatabase());
  if (!store) return Error{store.error()};

  EventHub events;
  SinkGuard log_events(std::make_shared<EventLogSink>(&events));
  DeviceSupervisor devices(
      *rig, std::chrono::milliseconds(static_cast<int>(1000 * config.device_poll_s)),
      // Every lease and return says so: previews at 1 Hz from many
      // pages would flood the streams; the latest state always arrives.
      [&events](const nlohmann::json& d) { events.PublishThrottled("devices", "devices", d); });
  const std::unique_ptr<UsbWatcher> usb = WatchUsb(config, &devices);
  JobRunner jobs(config, store->get(), &devices, &events);
  HttpApi api({&config, *token, store->get(), &devices, &events, &jobs});
  std::string why;
  if (!api.Bind(&why)) return Error{why};
  jobs.RecoverAfterRestart();
  std::thread server([&api] { api.Serve(); });
  Log().info("topostationd listening on {}:{}", config.listen_address, config.listen_port);

  HeadlessScheduler headless(config, &devices, &jobs);
  sd_notify(0, "READY=1");
  std::string last_status;
  while (!stop) {
    if (devices.Healthy()) sd_notify(0, "WATCHDOG=1");  // a stuck poll lets systemd restart us
    const std::string status = SystemdStatus(jobs.CurrentJob(), devices.WhyNotReady());
    if (status != last_status) sd_notifyf(0, "STATUS=%s", status.c_str());
    last_status = status;
    headless.Tick();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  sd_notify(0, "STOPPING=1");
  events.Close();
  api.Stop();
  server.join();
  return {};
}

}  // namespace ts::daemon
