#pragma once
// A test fixture: topostationd (a process of its own) driving the simulated station on
// loopback, with the simulated rig's true calibration. For the system tests of the daemon and
// of its page; each test runs in a network namespace of its own (scripts/netns-run).
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <thread>

#include "processing/io/calibration_yaml.h"
#include "sim/served_calibration.h"
#include "sim/sim_server.h"
#include "tests/common/daemon_process.h"
#include "tests/common/temp_dir.h"

namespace ts::testing {

using namespace std::chrono_literals;

inline const nlohmann::json kSurvey = {{"kind", "survey"},   {"station", "S1"},
                                       {"line", "L7"},       {"instrument_height_m", 1.52},
                                       {"operator", "test"}, {"single_row", true}};

class SimDaemonTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::SimStationOptions options;
    options.scene = "hills";
    options.seed = 2;
    station_ = *sim::BuildSimStation(options);
  }

  // The scene, or calibration targets in its place.
  void Serve(const sim::ServedCalibration& targets = {}) {
    sim::SimServeOptions o;
    o.stage_port = kStagePort;
    o.stage_pty = false;
    o.calibration = targets;
    // The jobs' flow is tested here, not the DEM's accuracy: a quarter of the render time.
    o.render.supersampling = 1;
    auto server = sim::SimServer::Start(station_, o);
    ASSERT_TRUE(server.ok()) << server.error();
    server_ = std::move(*server);
  }

  // The simulated rig with its true calibration (matching, not calibration, is tested here),
  // or the one given.
  std::string WriteRig(const Calibration* calibration = nullptr) {
    const std::string cal = dir_ / "calibration.yaml", rig = dir_ / "rig.yaml";
    EXPECT_TRUE(SaveCalibrationYaml(calibration ? *calibration : station_->rig.truth, cal).ok());
    std::ofstream(rig) << "schema_version: 1\nname: simulated-rig\ndevices:\n"
                       << "  left_camera: {id: TS-SIM-L}\n  right_camera: {id: TS-SIM-R}\n"
                       << "  stage: {transport: tcp, host: 127.0.0.1, port: " << kStagePort
                       << "}\ncalibration_file: calibration.yaml\n";
    return rig;
  }

  std::unique_ptr<DaemonProcess> StartDaemon(const std::string& extra_yaml = "",
                                             const Calibration* calibration = nullptr) {
    auto d = std::make_unique<DaemonProcess>(dir_.path().string(), kApiPort, WriteRig(calibration),
                                             extra_yaml);
    EXPECT_TRUE(d->Start()) << d->log();
    return d;
  }

  // Up to 30 s: under a whole `make test` on 2 cores, 10 s was once too short (the page's test
  // then failed before it began).
  static bool WaitReady(const DaemonProcess& d) {
    for (int i = 0; i < 300; ++i) {
      const nlohmann::json s = d.GetJson("/status");
      if (s.is_object() && s["ready"] == true) return true;
      std::this_thread::sleep_for(100ms);
    }
    return false;
  }

  // Starts a survey and returns its job id (0 when refused).
  static int64_t StartSurvey(const DaemonProcess& d, nlohmann::json body = kSurvey) {
    auto r = d.Post("/jobs", body);
    if (!r || r->status != 201) return 0;
    return nlohmann::json::parse(r->body)["id"].get<int64_t>();
  }

  static int PairsDone(const DaemonProcess& d) {
    const nlohmann::json job = d.GetJson("/status")["current_job"];
    return job.is_object() ? job.value("pairs_done", 0) : 0;
  }

  // Waits (up to 30 s) until the running job has taken `pairs`; the pairs it has then.
  static int WaitForPairs(const DaemonProcess& d, int pairs) {
    for (int i = 0; i < 600 && PairsDone(d) < pairs; ++i) std::this_thread::sleep_for(50ms);
    return PairsDone(d);
  }

  static constexpr int kStagePort = 15320;
  static constexpr int kApiPort = 18321;
  static std::shared_ptr<const sim::SimStation> station_;
  testing::TempDir dir_;
  std::unique_ptr<sim::SimServer> server_;
};
inline std::shared_ptr<const sim::SimStation> SimDaemonTest::station_;

}  // namespace ts::testing
