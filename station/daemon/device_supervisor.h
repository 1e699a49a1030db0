#pragma once
// The daemon's hold on the rig: each device's state from a poll (cameras by Aravis discovery,
// the stage by a Modbus status read over a connection the supervisor keeps, reopened with
// backoff), and the rig lent to one job at a time. It never moves the stage itself.
//
// Threads: the poll runs on its own thread; everything else may be called from any.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "acquisition/rig_config.h"
#include "devices/stage.h"

namespace ts::daemon {

enum class DeviceState { kAbsent, kPresent, kInUse, kError };
const char* DeviceStateName(DeviceState state);

struct DeviceStatus {
  DeviceState state = DeviceState::kAbsent;
  std::string reason;  // why absent or in error; who uses it
  std::string describe;
  bool operator==(const DeviceStatus&) const = default;
  nlohmann::json ToJson() const;
};

struct StageReading {
  double pan_deg = NAN, tilt_deg = NAN;
  double inclinometer_x_deg = NAN, inclinometer_y_deg = NAN;
  double temperature_c = NAN;
  nlohmann::json ToJson() const;
};

class DeviceSupervisor;

// The rig, lent to one user: the stage (opened by the supervisor, polled by no one while
// lent) and the right to open the cameras. Returned to the supervisor when destroyed.
class RigLease {
 public:
  ~RigLease();
  RigLease(const RigLease&) = delete;
  RigLease& operator=(const RigLease&) = delete;
  // The stage, opened now if the poll had not; an error says why it cannot be reached.
  Result<Stage*> stage();

 private:
  friend class DeviceSupervisor;
  explicit RigLease(DeviceSupervisor* owner) : owner_(owner) {}
  DeviceSupervisor* owner_;
};

class DeviceSupervisor {
 public:
  using OnChange = std::function<void(const nlohmann::json& devices)>;
  DeviceSupervisor(RigConfig rig, std::chrono::milliseconds poll_interval, OnChange on_change);
  ~DeviceSupervisor();

  // A preview or a stage command holds the rig for seconds: a job or a stage command that finds
  // it lent so waits for it, up to kBriefLeaseWait, rather than being refused. A preview never
  // waits (it shows the last frame instead).
  enum class LeaseKind { kJob, kCommand, kPreview };
  static constexpr std::chrono::seconds kBriefLeaseWait{15};
  // nullptr, with `*holder` saying who has it, when the rig is lent already.
  std::unique_ptr<RigLease> TryLease(const std::string& user, std::string* holder,
                                     LeaseKind kind = LeaseKind::kJob);
  // A device's USB presence (from the hotplug watcher), for devices the config names a USB
  // device for: while unplugged it is absent with that reason, whatever else the poll sees.
  void SetUsbPresence(const std::string& device, const std::string& usb_id, bool present);
  // Stops the stage now, whoever holds it (a lent stage is interrupted: its job fails).
  Status StopStage();

  // {"left_camera": DeviceStatus, "right_camera": ..., "stage": ...}
  nlohmann::json DevicesJson() const;
  StageReading stage_reading() const;
  // Empty when every device is present (or in use); else why the rig cannot capture.
  std::string WhyNotReady() const;
  // The poll loop went round within the last few intervals (feeds the systemd watchdog).
  bool Healthy() const;
  const RigConfig& rig() const { return rig_; }

 private:
  friend class RigLease;
  void PollLoop();
  void PollCameras();
  void PollStage();
  void SetStatus(DeviceStatus* device, DeviceStatus now);
  // Why `device` is unplugged (empty when it is not, or has no USB device); mutex_ held.
  std::string UnpluggedLocked(const std::string& device) const;
  void Return();
  nlohmann::json DevicesJsonLocked() const;

  const RigConfig rig_;
  const std::chrono::milliseconds interval_;
  const OnChange on_change_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool quit_ = false;
  std::string lent_to_;  // empty: not lent
  LeaseKind lent_kind_ = LeaseKind::kJob;
  int waiting_ = 0;  // jobs and commands waiting for a brief lease to end
  bool polling_ = false;
  bool poll_now_ = false;  // the poll thread is using stage_
  DeviceStatus left_, right_, stage_status_;
  StageReading reading_;
  std::map<std::string, std::string> unplugged_;  // device -> its USB id, while unplugged
  std::unique_ptr<Stage> stage_;  // touched by the poll thread, or by the lease holder
  std::chrono::steady_clock::time_point next_stage_attempt_{};
  std::chrono::seconds stage_backoff_{1};
  std::chrono::steady_clock::time_point last_round_ = std::chrono::steady_clock::now();
  std::thread thread_;
};

}  // namespace ts::daemon
