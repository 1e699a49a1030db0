#pragma once
// `sim serve`: the whole simulated station on the network. Two GigE Vision cameras (left on
// 127.0.0.1 as TS-SIM-L, right on 127.0.0.2 as TS-SIM-R by default) that render the view of
// the stage's current pose, and the stage on Modbus TCP (127.0.0.1:15020) and Modbus RTU on a
// pseudo-terminal, with the requested faults. 127.0.0.2 must be an address of lo (as root:
// `ip addr add 127.0.0.2/8 dev lo`; otherwise inside `unshare -rn`, see scripts/netns-run).
#include <condition_variable>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "core/result.h"
#include "sim/faults.h"
#include "sim/sim_station.h"
#include "sim/simulated_camera.h"
#include "sim/simulated_stage.h"

namespace ts::sim {

struct SimServeOptions {
  std::string left_address = "127.0.0.1";
  std::string right_address = "127.0.0.2";
  std::string left_serial = "TS-SIM-L";
  std::string right_serial = "TS-SIM-R";
  // Where the fake cameras hide behind the gvsp-loss relay (only with that fault).
  std::string left_hidden_address = "127.0.0.11";
  std::string right_hidden_address = "127.0.0.12";
  std::string stage_address = "127.0.0.1";
  int stage_port = 15020;
  bool stage_pty = true;  // also serve Modbus RTU on a pseudo-terminal
  SimFaults faults;
  RenderOptions render;
};

class SimServer {
 public:
  static Result<std::unique_ptr<SimServer>> Start(std::shared_ptr<const SimStation> station,
                                                  const SimServeOptions& options);
  ~SimServer();

  // {"left_camera": {"address", "serial"}, "right_camera": {...}, "stage_tcp": "host:port",
  //  "stage_rtu": "/dev/pts/N"}
  nlohmann::json Endpoints() const;
  SimulatedStage& stage() { return *stage_; }
  SimulatedCamera& camera(Side side) { return side == Side::kLeft ? *left_ : *right_; }

 private:
  SimServer() = default;
  void CameraGoneLoop(CameraGoneFault fault);

  SimServeOptions options_;
  std::string pty_path_;
  std::unique_ptr<SimulatedStage> stage_;
  std::unique_ptr<SimulatedCamera> left_, right_;
  std::mutex mutex_;
  std::condition_variable quit_changed_;
  bool quit_ = false;
  std::thread fault_thread_;
};

}  // namespace ts::sim
