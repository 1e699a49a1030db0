#include "sim/simulated_stage.h"

#include <fcntl.h>
#include <modbus/modbus.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

#include "core/stage_registers.h"
#include "processing/geometry/inclinometer.h"
#include "sim/noise.h"

namespace ts::sim {

namespace reg = stage_registers;

namespace {

constexpr double kPhysicsDt = 0.005;

void Put32(modbus_mapping_t* m, uint16_t address, uint32_t value) {
  m->tab_registers[address] = reg::High(value);
  m->tab_registers[address + 1] = reg::Low(value);
}

uint32_t Get32(const modbus_mapping_t* m, uint16_t address) {
  return reg::Join(m->tab_registers[address], m->tab_registers[address + 1]);
}

int32_t Millidegrees(double deg) { return static_cast<int32_t>(std::lround(deg * 1000.0)); }

}  // namespace

SimulatedStageOptions::SimulatedStageOptions() {
  tilt.speed_deg_s = 30.0;
  tilt.min_deg = -reg::kTiltLimitDeg;
  tilt.max_deg = reg::kTiltLimitDeg;
}

SimulatedStage::SimulatedStage(const SimulatedStageOptions& options)
    : options_(options),
      pan_(options.pan, Hash(options.seed, 0x9a11, 1)),
      tilt_(options.tilt, Hash(options.seed, 0x7117, 2)),
      rng_state_(Hash(options.seed, 0xfa17, 3)) {
  mapping_ = modbus_mapping_new_start_address(0, 0, 0, 0, 0, reg::kRegisterCount, 0, 0);
  uint16_t* r = mapping_->tab_registers;
  r[reg::kModelId] = reg::kModel;
  r[reg::kProtocolVersion] = reg::kVersion;
  Put32(mapping_, reg::kSerial, options.serial);
  r[reg::kTemperature] = static_cast<uint16_t>(int16_t{215});  // 21.5 degC
  for (const auto& [base, axis] :
       {std::pair{reg::kPanBase, &options.pan}, std::pair{reg::kTiltBase, &options.tilt}}) {
    Put32(mapping_, base + reg::kSpeed, static_cast<uint32_t>(axis->speed_deg_s * 1000));
    Put32(mapping_, base + reg::kAcceleration,
          static_cast<uint32_t>(axis->acceleration_deg_s2 * 1000));
  }
  PublishRegisters();
  threads_.emplace_back([this] { PhysicsLoop(); });
}

SimulatedStage::~SimulatedStage() {
  Stop();
  for (void* ctx : contexts_) modbus_free(static_cast<modbus_t*>(ctx));
  for (int fd : fds_) ::close(fd);
  modbus_mapping_free(mapping_);
}

void SimulatedStage::Stop() {
  stop_ = true;
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
}

StagePose SimulatedStage::Pose() const {
  std::lock_guard lock(mutex_);
  return {pan_.position_deg(), tilt_.position_deg()};
}

StagePose SimulatedStage::RestingPose(const StagePose& target) const {
  std::lock_guard lock(mutex_);
  // The target as the register holds it (millidegrees), as a move takes it.
  auto registered = [](double deg) { return Millidegrees(deg) / 1000.0; };
  return {pan_.RestingDeg(registered(target.pan_deg)),
          tilt_.RestingDeg(registered(target.tilt_deg))};
}

void SimulatedStage::SetOnMoveStarted(std::function<void(const StagePose&)> callback) {
  std::lock_guard lock(mutex_);
  on_move_started_ = std::move(callback);
}

void SimulatedStage::SetViewReady(std::function<bool(const StagePose&)> ready) {
  std::lock_guard lock(mutex_);
  view_ready_ = std::move(ready);
  awaiting_view_ = false;
}

void SimulatedStage::ApplyCommands() {
  for (const auto& [base, axis] :
       {std::pair{reg::kPanBase, &pan_}, std::pair{reg::kTiltBase, &tilt_}}) {
    uint16_t& command = mapping_->tab_registers[base + reg::kCommand];
    if (command == reg::kStart || command == reg::kHome) {
      // Both axes' commands arrive in separate requests: announce once both are in.
      announce_in_ticks_ = 4;
      awaiting_view_ = static_cast<bool>(view_ready_);
      ++inclinometer_draw_;
    }
    switch (command) {
      case reg::kStart:
        axis->Start(static_cast<int32_t>(Get32(mapping_, base + reg::kTarget)) / 1000.0,
                    Get32(mapping_, base + reg::kSpeed) / 1000.0,
                    Get32(mapping_, base + reg::kAcceleration) / 1000.0);
        break;
      case reg::kHome:
        axis->Home();
        break;
      case reg::kStop:
        axis->Stop();
        break;
      case reg::kAlarmReset:
        axis->ResetAlarm();
        break;
      default:
        break;
    }
    command = reg::kNone;  // taken
  }
}

void SimulatedStage::PublishRegisters() {
  Eigen::Vector2d tilt = InclinometerReads(options_.levelling, pan_.position_deg(),
                                           options_.inclinometer_index_error_deg);
  for (int axis = 0; axis < 2; ++axis)
    tilt[axis] += options_.inclinometer_noise_deg *
                  HashGaussian(options_.seed, 0x1c11, inclinometer_draw_, axis);
  for (const auto& [address, deg] :
       {std::pair{reg::kInclinometerX, tilt.x()}, std::pair{reg::kInclinometerY, tilt.y()}})
    Put32(mapping_, address,
          static_cast<uint32_t>(static_cast<int32_t>(std::lround(deg * M_PI / 180.0 * 1e6))));
  for (const auto& [base, axis] :
       {std::pair{reg::kPanBase, &pan_}, std::pair{reg::kTiltBase, &tilt_}}) {
    Put32(mapping_, base + reg::kActual, static_cast<uint32_t>(Millidegrees(axis->position_deg())));
    uint16_t status = 0;
    if (axis->homed() && !axis->alarm() && !axis->moving()) status |= reg::kReady;
    if (axis->moving() || axis->settling()) status |= reg::kMoving;
    if (axis->in_position() && !awaiting_view_) status |= reg::kInPosition;
    if (axis->homed()) status |= reg::kHomed;
    if (axis->alarm()) status |= reg::kAlarm;
    if (axis->limit()) status |= reg::kLimit;
    mapping_->tab_registers[base + reg::kStatus] = status;
    mapping_->tab_registers[base + reg::kAlarmCode] = axis->alarm_code();
  }
}

void SimulatedStage::PhysicsLoop() {
  auto next = std::chrono::steady_clock::now();
  while (!stop_) {
    next += std::chrono::microseconds(static_cast<int>(kPhysicsDt * 1e6));
    std::this_thread::sleep_until(next);
    std::function<void(const StagePose&)> notify;
    std::function<bool(const StagePose&)> ready;
    StagePose goal;
    {
      std::lock_guard lock(mutex_);
      ApplyCommands();
      pan_.Step(kPhysicsDt);
      tilt_.Step(kPhysicsDt);
      PublishRegisters();
      if (announce_in_ticks_ > 0 && --announce_in_ticks_ == 0) {
        announced_goal_ = {pan_.goal_deg(), tilt_.goal_deg()};
        notify = on_move_started_;
      }
      goal = announced_goal_;
      if (awaiting_view_ && announce_in_ticks_ <= 0) ready = view_ready_;
    }
    if (notify) notify(goal);
    if (ready && ready(goal)) {
      std::lock_guard lock(mutex_);
      awaiting_view_ = false;  // still this move's view: commands apply on this thread only
    }
  }
}

int SimulatedStage::HandleRequest(void* context, int fd, bool rtu) {
  modbus_t* ctx = static_cast<modbus_t*>(context);
  uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH > MODBUS_TCP_MAX_ADU_LENGTH ? MODBUS_RTU_MAX_ADU_LENGTH
                                                                      : MODBUS_TCP_MAX_ADU_LENGTH];
  modbus_set_socket(ctx, fd);
  const int length = modbus_receive(ctx, query);
  if (length <= 0) return length;
  bool drop, corrupt;
  {
    std::lock_guard lock(mutex_);
    const double u1 = static_cast<double>(Hash(rng_state_++, 1, 0) >> 11) / 9007199254740992.0;
    const double u2 = static_cast<double>(Hash(rng_state_++, 2, 0) >> 11) / 9007199254740992.0;
    drop = u1 < options_.drop_reply_ratio;
    corrupt = u2 < options_.corrupt_reply_ratio;
  }
  if (drop) return length;
  // Let libmodbus build the reply into a socket pair, so a fault can corrupt it on the way.
  int pair[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM, 0, pair) != 0) return -1;
  {
    std::lock_guard lock(mutex_);
    modbus_set_socket(ctx, pair[0]);
    modbus_reply(ctx, query, length, mapping_);
    modbus_set_socket(ctx, fd);
  }
  uint8_t reply[512];
  const ssize_t n = ::recv(pair[1], reply, sizeof(reply), MSG_DONTWAIT);
  ::close(pair[0]);
  ::close(pair[1]);
  if (n <= 0) return length;
  // RTU: a flipped CRC byte; TCP: a flipped transaction id (TCP carries no CRC).
  if (corrupt) reply[rtu ? n - 1 : 0] ^= 0x5A;
  ssize_t written = 0;
  while (written < n) {
    const ssize_t w = ::write(fd, reply + written, static_cast<size_t>(n - written));
    if (w <= 0) return -1;
    written += w;
  }
  return length;
}

Status SimulatedStage::ListenTcp(const std::string& address, int port) {
  modbus_t* ctx = modbus_new_tcp(address.c_str(), port);
  if (!ctx) return Error{"simulated stage: cannot create Modbus TCP context"};
  modbus_set_slave(ctx, 1);
  const int listen_fd = modbus_tcp_listen(ctx, 4);
  if (listen_fd < 0) {
    modbus_free(ctx);
    return Error{"simulated stage: cannot listen on " + address + ":" + std::to_string(port) +
                 ": " + modbus_strerror(errno)};
  }
  contexts_.push_back(ctx);
  fds_.push_back(listen_fd);
  threads_.emplace_back([this, listen_fd, ctx] { ServeTcpLoop(listen_fd, ctx); });
  return {};
}

void SimulatedStage::ServeTcpLoop(int listen_fd, void* ctx) {
  std::vector<int> clients;
  while (!stop_) {
    fd_set read_set;
    FD_ZERO(&read_set);
    FD_SET(listen_fd, &read_set);
    int max_fd = listen_fd;
    for (int c : clients) FD_SET(c, &read_set), max_fd = std::max(max_fd, c);
    timeval timeout{0, 100000};
    if (::select(max_fd + 1, &read_set, nullptr, nullptr, &timeout) <= 0) continue;
    if (FD_ISSET(listen_fd, &read_set)) {
      const int client = ::accept(listen_fd, nullptr, nullptr);
      if (client >= 0) clients.push_back(client);
    }
    for (size_t i = 0; i < clients.size();) {
      if (FD_ISSET(clients[i], &read_set)) {
        const int rc = HandleRequest(ctx, clients[i], false);
        if (rc == -1 && errno != EMBBADCRC && errno != EMBBADDATA) {
          ::close(clients[i]);
          clients.erase(clients.begin() + static_cast<long>(i));
          continue;
        }
      }
      ++i;
    }
  }
  for (int c : clients) ::close(c);
}

Result<std::string> SimulatedStage::ServePty() {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0)
    return Error{"simulated stage: cannot create a pseudo-terminal"};
  const char* name = ::ptsname(master);
  if (!name) return Error{"simulated stage: no pseudo-terminal name"};
  const std::string path = name;
  // The RTU context is never connected: it reads and writes the pty master directly.
  modbus_t* ctx = modbus_new_rtu(path.c_str(), 115200, 'N', 8, 1);
  if (!ctx) return Error{"simulated stage: cannot create Modbus RTU context"};
  modbus_set_slave(ctx, 1);
  modbus_set_indication_timeout(ctx, 0, 100000);
  contexts_.push_back(ctx);
  fds_.push_back(master);
  threads_.emplace_back([this, master, ctx] { ServeRtuLoop(master, ctx); });
  return path;
}

void SimulatedStage::ServeRtuLoop(int master_fd, void* ctx) {
  while (!stop_) {
    const int rc = HandleRequest(ctx, master_fd, true);
    // EIO: nobody holds the terminal open yet; wait for a client.
    if (rc == -1 && errno == EIO) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace ts::sim
