#include "station/daemon/device_supervisor.h"

#include <algorithm>
#include <tuple>

#include "devices/aravis_camera.h"
#include "devices/modbus_stage.h"

namespace ts::daemon {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::chrono::seconds kMaxBackoff{30};

nlohmann::json NumberOrNull(double v) {
  if (std::isnan(v)) return nullptr;
  return v;
}

std::string DescribeStage(const StageEndpoint& s) {
  if (s.transport == StageTransport::kTcp)
    return "Modbus TCP " + s.host + ":" + std::to_string(s.port);
  return "Modbus RTU " + s.device;
}

}  // namespace

const char* DeviceStateName(DeviceState state) {
  switch (state) {
    case DeviceState::kAbsent:
      return "absent";
    case DeviceState::kPresent:
      return "present";
    case DeviceState::kInUse:
      return "in_use";
    case DeviceState::kError:
      return "error";
  }
  return "error";
}

nlohmann::json DeviceStatus::ToJson() const {
  return {{"state", DeviceStateName(state)}, {"reason", reason}, {"device", describe}};
}

nlohmann::json StageReading::ToJson() const {
  return {{"pan_deg", NumberOrNull(pan_deg)},
          {"tilt_deg", NumberOrNull(tilt_deg)},
          {"inclinometer_x_deg", NumberOrNull(inclinometer_x_deg)},
          {"inclinometer_y_deg", NumberOrNull(inclinometer_y_deg)},
          {"temperature_c", NumberOrNull(temperature_c)}};
}

RigLease::~RigLease() { owner_->Return(); }

Result<Stage*> RigLease::stage() {
  DeviceSupervisor& s = *owner_;
  if (!s.stage_) {
    auto opened = OpenModbusStage(s.rig_.stage);
    if (!opened) return Error{opened.error()};
    s.stage_ = std::move(*opened);
  }
  return s.stage_.get();
}

DeviceSupervisor::DeviceSupervisor(RigConfig rig, std::chrono::milliseconds poll_interval,
                                   OnChange on_change)
    : rig_(std::move(rig)), interval_(poll_interval), on_change_(std::move(on_change)) {
  left_.describe = "camera " + rig_.left_camera.id;
  right_.describe = "camera " + rig_.right_camera.id;
  stage_status_.describe = DescribeStage(rig_.stage);
  left_.reason = right_.reason = stage_status_.reason = "not looked for yet";
  thread_ = std::thread([this] { PollLoop(); });
}

DeviceSupervisor::~DeviceSupervisor() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
    wake_.notify_all();
  }
  thread_.join();
}

std::unique_ptr<RigLease> DeviceSupervisor::TryLease(const std::string& user, std::string* holder,
                                                     LeaseKind kind) {
  std::unique_lock lock(mutex_);
  auto brief = [](LeaseKind k) { return k != LeaseKind::kJob; };
  if (kind == LeaseKind::kPreview && waiting_ > 0) {  // a job or command goes first
    if (holder) *holder = "a job about to start";
    return nullptr;
  }
  if (kind != LeaseKind::kPreview) {
    ++waiting_;
    wake_.wait_for(lock, kBriefLeaseWait, [&] { return lent_to_.empty() || !brief(lent_kind_); });
    --waiting_;
  }
  if (!lent_to_.empty()) {
    if (holder) *holder = lent_to_;
    return nullptr;
  }
  lent_to_ = user;
  lent_kind_ = kind;
  for (DeviceStatus* d : {&left_, &right_, &stage_status_})
    if (d->state == DeviceState::kPresent) *d = {DeviceState::kInUse, user, d->describe};
  const nlohmann::json devices = DevicesJsonLocked();
  lock.unlock();
  if (on_change_) on_change_(devices);
  // The poll may be reading the stage: it holds stage_ only between two checks of lent_to_,
  // which the lease now blocks; wait for that round to end.
  std::unique_lock round(mutex_);
  wake_.wait(round, [&] { return !polling_; });
  return std::unique_ptr<RigLease>(new RigLease(this));
}

void DeviceSupervisor::Return() {
  nlohmann::json devices;
  {
    std::lock_guard lock(mutex_);
    if (stage_ && stage_->interrupted()) stage_.reset();  // a stopped job's stage: open anew
    lent_to_.clear();
    for (DeviceStatus* d : {&left_, &right_, &stage_status_})
      if (d->state == DeviceState::kInUse) d->state = DeviceState::kPresent, d->reason.clear();
    poll_now_ = true;  // the job may have lost a device
    wake_.notify_all();
    devices = DevicesJsonLocked();
  }
  // No longer in use: said now, as the lease said "in use" (the poll reports only changes).
  if (on_change_) on_change_(devices);
}

Status DeviceSupervisor::StopStage() {
  {
    std::lock_guard lock(mutex_);
    if (!lent_to_.empty()) {
      if (stage_) stage_->Interrupt();
      return {};
    }
  }
  std::string holder;
  auto lease = TryLease("stop", &holder, LeaseKind::kCommand);
  if (!lease) {  // lent in between: interrupt that user
    std::lock_guard lock(mutex_);
    if (stage_) stage_->Interrupt();
    return {};
  }
  Result<Stage*> stage = lease->stage();
  if (!stage) return Error{stage.error()};
  return (*stage)->Stop();
}

nlohmann::json DeviceSupervisor::DevicesJson() const {
  std::lock_guard lock(mutex_);
  return DevicesJsonLocked();
}

nlohmann::json DeviceSupervisor::DevicesJsonLocked() const {
  return {{"left_camera", left_.ToJson()},
          {"right_camera", right_.ToJson()},
          {"stage", stage_status_.ToJson()}};
}

StageReading DeviceSupervisor::stage_reading() const {
  std::lock_guard lock(mutex_);
  return reading_;
}

std::string DeviceSupervisor::WhyNotReady() const {
  std::lock_guard lock(mutex_);
  for (const DeviceStatus* d : {&left_, &right_, &stage_status_})
    if (d->state == DeviceState::kAbsent || d->state == DeviceState::kError)
      return d->describe + " is " + DeviceStateName(d->state) + ": " + d->reason;
  return "";
}

bool DeviceSupervisor::Healthy() const {
  std::lock_guard lock(mutex_);
  return Clock::now() - last_round_ < 3 * interval_ + std::chrono::seconds(10);
}

void DeviceSupervisor::SetUsbPresence(const std::string& device, const std::string& usb_id,
                                      bool present) {
  std::lock_guard lock(mutex_);
  if (present)
    unplugged_.erase(device);
  else
    unplugged_[device] = usb_id;
  poll_now_ = true;
  wake_.notify_all();
}

std::string DeviceSupervisor::UnpluggedLocked(const std::string& device) const {
  auto it = unplugged_.find(device);
  if (it == unplugged_.end()) return "";
  return "its USB device " + it->second + " is unplugged";
}

void DeviceSupervisor::SetStatus(DeviceStatus* device, DeviceStatus now) {
  // Called with mutex_ held by the poll thread; a lent device stays "in use".
  if (device->state == DeviceState::kInUse) return;
  now.describe = device->describe;
  *device = std::move(now);
}

void DeviceSupervisor::PollCameras() {
  {
    std::lock_guard lock(mutex_);
    if (!lent_to_.empty()) return;  // in use: no discovery traffic beside a capture
  }
  const std::vector<CameraInfo> seen = ListAravisCameras();  // discovery: no camera is opened
  auto status_of = [&](const CameraEndpoint& e) {
    const bool found = std::any_of(seen.begin(), seen.end(), [&](const CameraInfo& c) {
      return c.id == e.id || c.serial == e.id || c.address == e.id;
    });
    if (found) return DeviceStatus{DeviceState::kPresent, "", ""};
    return DeviceStatus{DeviceState::kAbsent, "not found by Aravis discovery", ""};
  };
  std::lock_guard lock(mutex_);
  if (!lent_to_.empty()) return;
  for (auto [status, endpoint, name] : {std::tuple{&left_, &rig_.left_camera, "left_camera"},
                                        std::tuple{&right_, &rig_.right_camera, "right_camera"}}) {
    const std::string unplugged = UnpluggedLocked(name);
    SetStatus(status, unplugged.empty() ? status_of(*endpoint)
                                        : DeviceStatus{DeviceState::kAbsent, unplugged, ""});
  }
}

void DeviceSupervisor::PollStage() {
  // The poll thread owns stage_ between here and the end, unless a lease began before.
  {
    std::lock_guard lock(mutex_);
    if (!lent_to_.empty()) return;
    if (const std::string unplugged = UnpluggedLocked("stage"); !unplugged.empty()) {
      SetStatus(&stage_status_, {DeviceState::kAbsent, unplugged, ""});
      reading_ = {};
      if (stage_) stage_.reset();  // its serial port is gone with it
      return;
    }
    if (Clock::now() < next_stage_attempt_) return;
    polling_ = true;
  }
  DeviceStatus status{DeviceState::kPresent, "", ""};
  StageReading reading;
  if (!stage_) {
    auto opened = OpenModbusStage(rig_.stage);
    if (opened)
      stage_ = std::move(*opened);
    else
      status = {DeviceState::kAbsent, opened.error(), ""};
  }
  if (stage_) {
    const Result<StageInfo> info = stage_->Identify();
    const Result<AxisState> pan = info ? stage_->ReadAxis(Axis::kPan) : Error{info.error()};
    const Result<AxisState> tilt = pan ? stage_->ReadAxis(Axis::kTilt) : Error{pan.error()};
    if (!tilt) {
      status = {DeviceState::kError, tilt.error(), ""};
      stage_.reset();
    } else {
      reading = {pan->position_deg, tilt->position_deg, info->inclinometer_x_deg,
                 info->inclinometer_y_deg, info->temperature_c};
      if (pan->alarm() || tilt->alarm())
        status = {DeviceState::kError,
                  std::string("alarm on the ") + (pan->alarm() ? "pan" : "tilt") + " axis", ""};
    }
  }
  std::lock_guard lock(mutex_);
  polling_ = false;
  wake_.notify_all();
  if (status.state == DeviceState::kPresent) {
    stage_backoff_ = std::chrono::seconds(1);
  } else {  // reopen after 1, 2, 4 ... 30 s
    next_stage_attempt_ = Clock::now() + stage_backoff_;
    stage_backoff_ = std::min(2 * stage_backoff_, kMaxBackoff);
  }
  reading_ = reading;
  SetStatus(&stage_status_, status);
}

void DeviceSupervisor::PollLoop() {
  nlohmann::json reported;
  std::unique_lock lock(mutex_);
  while (!quit_) {
    lock.unlock();
    PollCameras();
    PollStage();
    lock.lock();
    last_round_ = Clock::now();
    nlohmann::json devices = DevicesJsonLocked();
    if (devices != reported) {
      reported = devices;
      lock.unlock();
      if (on_change_) on_change_(devices);
      lock.lock();
    }
    wake_.wait_for(lock, interval_, [&] { return quit_ || poll_now_; });
    poll_now_ = false;
  }
}

}  // namespace ts::daemon
