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
#include <vector>

#include "core/result.h"
#include "sim/faults.h"
#include "sim/served_calibration.h"
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
  ServedCalibration calibration;  // targets shown instead of the scene
  // Stage targets whose views are rendered before the server starts, so that the capture's
  // own time can be measured apart from rendering (`sim serve --prerender`).
  std::vector<StagePose> prerender_targets;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("left_address", self.left_address, {"left camera's address (of lo)"});
    v("right_address", self.right_address, {"right camera's address (of lo)"});
    v("left_serial", self.left_serial, {"left camera's serial number"});
    v("right_serial", self.right_serial, {"right camera's serial number"});
    v("stage_address", self.stage_address, {"stage's Modbus TCP address"});
    v("stage_port", self.stage_port, {"stage's Modbus TCP port", "", 1, 65535});
    v("stage_pty", self.stage_pty, {"also serve Modbus RTU on a pseudo-terminal"});
    v.Group("render", self.render);
    v.Group("calibration", self.calibration);
  }
};

// The row of poses a capture with the simulated rig's design calibration (config/sim-rig.yaml)
// and the default plan takes: what `sim serve --prerender` renders ahead.
std::vector<StagePose> DesignPlanTargets(const SimStation& station);

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
