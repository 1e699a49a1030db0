#pragma once
// The simulated rotary stage on the network: the DESIGN.md register map served over Modbus
// TCP and Modbus RTU (on a pseudo-terminal it creates), with the dynamics of
// stage_dynamics.h and fault injection (corrupted and dropped replies). The real libmodbus
// server code answers, so a client sees exactly what a real stage would send.
//
// Threads: a physics thread (200 Hz) and one thread per transport; Pose() and the
// on-settled callback may be used from any thread.
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/result.h"
#include "processing/geometry/capture_plan.h"
#include "processing/geometry/stage_kinematics.h"
#include "sim/stage_dynamics.h"

struct _modbus_mapping_t;

namespace ts::sim {

struct SimulatedStageOptions {
  AxisSettings pan;   // default 60 deg/s, 180 deg/s^2, settling 0.2 s
  AxisSettings tilt;  // default 30 deg/s, soft limits +-32 deg
  // The inclinometer rides the pan (inclinometer.h): it reads this set-up's levelling (and pan
  // zero) turned by the encoder's pan, plus its index error and its noise: drawn anew with
  // every move, not with every tick of the simulation, so that a survey reads the same whatever
  // the machine's load.
  StageKinematics levelling;
  Eigen::Vector2d inclinometer_index_error_deg = Eigen::Vector2d::Zero();
  double inclinometer_noise_deg = 0.0;
  uint32_t serial = 7501001;
  double corrupt_reply_ratio = 0.0;  // fault modbus-crc: replies with a broken checksum
  double drop_reply_ratio = 0.0;     // fault modbus-drop: requests never answered
  uint64_t seed = 1;
  SimulatedStageOptions();
};

class SimulatedStage {
 public:
  explicit SimulatedStage(const SimulatedStageOptions& options);
  ~SimulatedStage();
  SimulatedStage(const SimulatedStage&) = delete;
  SimulatedStage& operator=(const SimulatedStage&) = delete;

  Status ListenTcp(const std::string& address, int port);
  // Creates a pseudo-terminal and serves Modbus RTU on it; returns the device path a client
  // opens (e.g. /dev/pts/3).
  Result<std::string> ServePty();
  // Encoder readings of the axes now (what the actual-position registers hold, unrounded).
  StagePose Pose() const;
  // Where a move to `target` will come to rest (the encoder readings then).
  StagePose RestingPose(const StagePose& target) const;
  // Called (on the physics thread) with the pose where the axes will come to rest, shortly
  // after a move starts, so that a simulated camera can render it while the stage moves.
  void SetOnMoveStarted(std::function<void(const StagePose&)> callback);
  // Until `ready` says the view at the announced pose has been rendered, the axes come to rest
  // without reporting IN_POSITION, so no trigger comes before the view exists: a real camera
  // exposes in its exposure time, but a simulated one that rendered on a trigger would hold up
  // the thread that also answers its control channel (seconds under load: the client lost it).
  void SetViewReady(std::function<bool(const StagePose&)> ready);
  void Stop();

 private:
  struct Transport;
  void PhysicsLoop();
  void ApplyCommands();
  void PublishRegisters();
  void ServeTcpLoop(int listen_fd, void* ctx);
  void ServeRtuLoop(int master_fd, void* ctx);
  // Receives one request on fd and answers it (or not, or corrupted: the faults).
  int HandleRequest(void* ctx, int fd, bool rtu);

  SimulatedStageOptions options_;
  mutable std::mutex mutex_;  // guards axes_, registers, rng_
  AxisDynamics pan_, tilt_;
  _modbus_mapping_t* mapping_ = nullptr;
  std::function<void(const StagePose&)> on_move_started_;
  int announce_in_ticks_ = -1;  // counts down to announcing the goal of a new move
  std::function<bool(const StagePose&)> view_ready_;
  bool awaiting_view_ = false;  // a move started and its view is not yet rendered
  StagePose announced_goal_;
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
  std::vector<void*> contexts_;
  std::vector<int> fds_;
  uint64_t rng_state_;
  uint64_t inclinometer_draw_ = 0;  // the axis commands to move or home taken so far
};

}  // namespace ts::sim
