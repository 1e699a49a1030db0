// Capture over the real drivers (Aravis, libmodbus) against the simulated station on loopback:
// a complete panorama, and each failure the field will bring (DESIGN.md "Reliability").
#include "acquisition/capture.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <atomic>

#include <chrono>
#include <fstream>
#include <optional>
#include <random>
#include <thread>

#include "devices/aravis_camera.h"
#include "devices/modbus_stage.h"
#include "processing/geometry/inclinometer.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/station_manifest.h"
#include "processing/io/station_validator.h"
#include "sim/sim_server.h"
#include "tests/common/sim_rig_config.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using namespace std::chrono_literals;

class CaptureTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::SimStationOptions options;
    options.scene = "hills";
    options.seed = 4;
    station_ = *sim::BuildSimStation(options);
  }

  // Starts the simulated hardware with faults; the stage on a port of its own. With
  // `prerender`, the default plan's views are rendered first (`sim serve --prerender`).
  void Serve(int port, const sim::SimFaults& faults = {},
             std::shared_ptr<const sim::SimStation> station = nullptr, bool prerender = false) {
    sim::SimServeOptions o;
    o.stage_port = port;
    o.faults = faults;
    // The capture's flow is tested here, not the images' edges: a quarter of the render time.
    o.render.supersampling = 1;
    if (prerender) o.prerender_targets = sim::DesignPlanTargets(station ? *station : *station_);
    auto server = sim::SimServer::Start(station ? station : station_, o);
    ASSERT_TRUE(server.ok()) << server.error();
    server_ = std::move(*server);
    port_ = port;
  }

  // A rig config for the simulated rig at the served endpoints (TCP, or RTU on the pty).
  std::string WriteRig(bool rtu = false) {
    const std::string stage =
        rtu ? "{transport: rtu, device: " + server_->Endpoints()["stage_rtu"].get<std::string>() +
                  ", rs485: true, inclinometer: base}"
            : testing::TcpStage(port_);
    return testing::WriteSimRigConfig(dir_ / "rig.yaml", stage);
  }

  struct Devices {
    std::unique_ptr<Stage> stage;
    std::unique_ptr<Camera> left, right;
  };
  Devices Open(const RigConfig& rig) {
    Devices d;
    auto stage = OpenModbusStage(rig.stage);
    auto left = OpenAravisCamera(rig.left_camera);
    auto right = OpenAravisCamera(rig.right_camera);
    EXPECT_TRUE(stage.ok() && left.ok() && right.ok());
    if (stage) d.stage = std::move(*stage);
    if (left) d.left = std::move(*left);
    if (right) d.right = std::move(*right);
    return d;
  }

  Result<CaptureSummary> Capture(const std::string& rig_file, bool resume,
                                 const CaptureOptions& options) {
    const Result<RigConfig> rig = LoadRigConfig(rig_file);
    if (!rig) return Error{rig.error()};
    Devices d = Open(*rig);
    if (!d.stage || !d.left || !d.right) return Error{"devices did not open"};
    return CaptureStation(*d.stage, *d.left, *d.right, *rig, dir_ / "S", resume, options);
  }

  static CaptureOptions Short(int azimuths) {
    CaptureOptions o;
    o.plan.azimuths = azimuths;
    o.initial_exposure_us = 4000;
    return o;
  }

  static std::shared_ptr<const sim::SimStation> station_;
  testing::TempDir dir_;
  std::unique_ptr<sim::SimServer> server_;
  int port_ = 0;
};
std::shared_ptr<const sim::SimStation> CaptureTest::station_;

TEST_F(CaptureTest, CapturesACompleteValidPanorama) {
  // Prerendered: the timeline is the stage's and the cameras' own, not the simulator's render
  // (a view still rendering holds the simulated stage short of IN_POSITION).
  Serve(15150, {}, nullptr, true);
  const Result<CaptureSummary> s = Capture(WriteRig(), false, CaptureOptions{});
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->total_pairs, 12);
  EXPECT_EQ(s->captured_now, 12);
  const Result<StationManifest> m = ValidateStation(dir_ / "S", {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  double stage_wait_s = 0.0;
  for (const PairRecord& p : m->pairs) {
    EXPECT_NEAR(p.readback.pan_deg, p.commanded.pan_deg, 0.05);
    EXPECT_NEAR(p.readback.tilt_deg, p.commanded.tilt_deg, 0.05);
    // The timeline: the simulated axes settle for 0.2 s (seen through a 20 ms status poll);
    // a pair's own time holds its wait for the stage and its triggers.
    const PairTimeline& t = p.timeline;
    EXPECT_GT(t.move_s, 0.0);
    EXPECT_NEAR(t.settle_s, 0.2, 0.1);
    EXPECT_GE(t.triggers, 1);
    EXPECT_GT(t.trigger_to_frame_s, 0.0);
    EXPECT_GE(t.verify_s, 0.0);
    EXPECT_GT(t.write_s, 0.0);
    EXPECT_GE(t.pair_s, t.stage_wait_s + t.trigger_to_frame_s + t.write_s);
    stage_wait_s += t.stage_wait_s;
  }
  EXPECT_NEAR(s->timeline["total_s"]["stage_wait_s"].get<double>(), stage_wait_s, 1e-9);
  EXPECT_EQ(s->timeline["pairs"].size(), 12u);
  // The stage's inclinometer reading at home is the station's levelling (to the reading's
  // noise, 0.002 deg); each pair holds its reading at its pan, and those round the circle fit
  // the true levelling, free of the index error.
  const sim::SimRig& rig = station_->rig;
  EXPECT_NEAR(m->calibration.stage.levelling_x_deg, rig.inclinometer_x_deg, 0.01);
  std::vector<InclinometerReading> readings;
  for (const PairRecord& pair : m->pairs) {
    ASSERT_TRUE(pair.inclinometer_deg) << pair.index;
    EXPECT_LT(
        (*pair.inclinometer_deg - sim::InclinometerReadsAt(rig, pair.readback.pan_deg)).norm(),
        0.01);
    readings.push_back({pair.readback.pan_deg, *pair.inclinometer_deg});
  }
  const std::optional<LevellingFit> fit =
      FitLevelling(readings, rig.truth.stage, rig.inclinometer_noise_deg);
  ASSERT_TRUE(fit);
  const Eigen::Vector2d truth(rig.truth.stage.levelling_x_deg, rig.truth.stage.levelling_y_deg);
  EXPECT_LT((fit->levelling_deg - truth).cwiseAbs().maxCoeff(), 4 * fit->levelling_sigma_deg);
  EXPECT_LT((fit->index_error_deg - rig.inclinometer_index_error_deg).norm(), 0.005);
  const PairRecord& p = m->pairs[3];
  const Result<cv::Mat> image =
      ReadMonoPng(dir_ / ("S/" + p.left.file), PixelFormat::kMono8, 1392, 1040);
  ASSERT_TRUE(image.ok());
  EXPECT_GT(cv::mean(*image)[0], 30.0);
}

// `sim serve --prerender` renders the poses a capture with config/sim-rig.yaml will take.
TEST_F(CaptureTest, SimServePrerendersThePlanOfTheSimulatedRigsConfig) {
  const Result<RigConfig> rig = LoadRigConfig(TS_SOURCE_DIR "/config/sim-rig.yaml");
  ASSERT_TRUE(rig.ok()) << rig.error();
  const std::vector<StagePose> plan = MakeCapturePlan(rig->calibration, CapturePlanOptions{});
  const std::vector<StagePose> prerendered = sim::DesignPlanTargets(*station_);
  ASSERT_EQ(plan.size(), prerendered.size());
  for (size_t i = 0; i < plan.size(); ++i) {
    EXPECT_NEAR(plan[i].pan_deg, prerendered[i].pan_deg, 1e-9);
    EXPECT_NEAR(plan[i].tilt_deg, prerendered[i].tilt_deg, 1e-9);
  }
}

TEST_F(CaptureTest, ModbusNoiseOnTheSerialLineIsRetriedAway) {
  sim::SimFaults faults;
  faults.modbus_crc = 0.05;
  faults.modbus_drop = 0.02;
  Serve(15151, faults);
  const Result<CaptureSummary> s = Capture(WriteRig(/*rtu=*/true), false, Short(4));
  ASSERT_TRUE(s.ok()) << s.error();
  const Result<StationManifest> m = ValidateStation(dir_ / "S", {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  // This rig's inclinometer is declared on the base: one reading, none per pose.
  for (const PairRecord& p : m->pairs) EXPECT_FALSE(p.inclinometer_deg) << p.index;
}

TEST_F(CaptureTest, OnePercentGvspLossStillGivesEveryImageValid) {
  sim::SimFaults faults;
  faults.gvsp_loss = 0.01;
  Serve(15159, faults);
  const Result<CaptureSummary> s = Capture(WriteRig(), false, Short(6));
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_GT(s->resent_packets, 50u);  // ~1 % of ~990 packets per frame, 12 frames
  const Result<StationManifest> m = ValidateStation(dir_ / "S", {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->pairs.size(), 6u);
}

TEST_F(CaptureTest, StageAlarmStopsWithAClearError) {
  sim::SimFaults faults;
  faults.stage_alarm = sim::AxisFault{true, 2};  // home, first pose, then the alarm
  Serve(15152, faults);
  const Result<CaptureSummary> s = Capture(WriteRig(), false, Short(4));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("pan axis alarm: overload (code 1)"), std::string::npos) << s.error();
  EXPECT_NE(s.error().find("stage stopped"), std::string::npos);
  EXPECT_NE(s.error().find("moving to pair 01"), std::string::npos) << s.error();
  const Result<StationManifest> m = ValidateStation(dir_ / "S");
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->pairs.size(), 1u);
}

TEST_F(CaptureTest, StageStallStopsWithAClearError) {
  sim::SimFaults faults;
  faults.stage_stall = sim::AxisFault{false, 1};  // tilt: homing works, the first move stalls
  Serve(15153, faults);
  const Result<CaptureSummary> s = Capture(WriteRig(), false, Short(4));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("tilt axis stalled"), std::string::npos) << s.error();
  EXPECT_TRUE(ValidateStation(dir_ / "S").ok());
}

TEST_F(CaptureTest, LostCameraStopsAndResumeCompletesWithoutDuplicates) {
  sim::SimFaults faults;
  faults.camera_gone = sim::CameraGoneFault{Side::kRight, 7.0, 25.0};
  Serve(15154, faults);
  const std::string rig = WriteRig();
  CaptureOptions o = Short(8);
  // A retry budget (about 10 s here) well inside the 25 s outage.
  o.frame_attempts = 2;
  o.frame_timeout = 2000ms;
  o.reconnect_budget = 2000ms;
  const Result<CaptureSummary> first = Capture(rig, false, o);
  ASSERT_FALSE(first.ok()) << "took " << first->seconds << " s";
  EXPECT_NE(first.error().find("camera TS-SIM-R lost at pair"), std::string::npos) << first.error();
  const Result<StationManifest> partial = ValidateStation(dir_ / "S");
  ASSERT_TRUE(partial.ok()) << partial.error();
  ASSERT_GT(partial->pairs.size(), 0u);
  ASSERT_LT(partial->pairs.size(), 8u);
  // Wait for the camera to come back, then resume.
  for (int i = 0; i < 400 && !server_->camera(Side::kRight).running(); ++i)
    std::this_thread::sleep_for(100ms);
  const Result<CaptureSummary> second = Capture(rig, true, o);
  ASSERT_TRUE(second.ok()) << second.error();
  EXPECT_EQ(second->already_present, static_cast<int>(partial->pairs.size()));
  EXPECT_EQ(second->captured_now, 8 - static_cast<int>(partial->pairs.size()));
  const Result<StationManifest> done = ValidateStation(dir_ / "S", {.require_complete = true});
  ASSERT_TRUE(done.ok()) << done.error();
  EXPECT_EQ(done->pairs.size(), 8u);
  for (const PairRecord& before : partial->pairs)  // what was there is untouched
    EXPECT_EQ(done->FindPair(before.index)->left.sha256, before.left.sha256);
}

TEST_F(CaptureTest, CameraBackWithinTheRetryBudgetIsReconnectedAndCaptureGoesOn) {
  sim::SimFaults faults;
  faults.camera_gone = sim::CameraGoneFault{Side::kLeft, 6.0, 2.0};
  Serve(15157, faults);
  CaptureOptions o = Short(8);
  o.frame_timeout = 2000ms;
  o.reconnect_budget = 6000ms;
  const Result<CaptureSummary> s = Capture(WriteRig(), false, o);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_GT(s->frame_retries, 0);  // the outage was seen, and survived
  EXPECT_TRUE(ValidateStation(dir_ / "S", {.require_complete = true}).ok());
}

// A laptop busy with something else: every core spinning while the capture runs, so frames
// come late. The cameras still answer, so the capture triggers again instead of giving up.
// With pair_budget = 0 (the old rule) this fails at the first late frame.
TEST_F(CaptureTest, WithEveryCoreBusyTheCaptureCompletes) {
  Serve(15158);
  std::atomic<bool> stop{false};
  std::vector<std::thread> load;
  for (unsigned k = 0; k < std::max(2u, std::thread::hardware_concurrency()); ++k)
    load.emplace_back([&stop] {
      volatile double x = 1.0;
      while (!stop) x = x * 1.0000001 + 1e-9;
    });
  CaptureOptions o = Short(6);
  o.frame_timeout = 150ms;  // shorter than a frame takes on a loaded machine
  o.frame_attempts = 1;     // one late frame would have counted the camera lost (it did)
  const Result<CaptureSummary> s = Capture(WriteRig(), false, o);
  stop = true;
  for (std::thread& t : load) t.join();
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ(s->captured_now, 6);
  EXPECT_TRUE(ValidateStation(dir_ / "S", {.require_complete = true}).ok());
}

TEST_F(CaptureTest, KillNineAtRandomMomentsNeverLeavesABrokenStation) {
  Serve(15155);
  const std::string rig = WriteRig();
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> delay_ms(500, 9000);
  for (int trial = 0; trial < 5; ++trial) {
    const bool resume = std::filesystem::exists(dir_ / "S/station.json");
    const pid_t pid = ::fork();
    if (pid == 0) {
      const std::string out = dir_ / "S";
      const char* argv[] = {TS_TOPOSTATION_EXE,
                            "capture",
                            "--rig",
                            rig.c_str(),
                            "--out",
                            out.c_str(),
                            "--azimuths",
                            "6",
                            "--exposure-us",
                            "4000",
                            resume ? "--resume" : "--json",
                            nullptr};
      ::execv(argv[0], const_cast<char**>(argv));
      ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    if (!std::filesystem::exists(dir_ / "S/station.json")) continue;  // killed before it began
    const Result<StationManifest> m = ValidateStation(dir_ / "S");
    ASSERT_TRUE(m.ok()) << "trial " << trial << ": " << m.error();
  }
  ASSERT_TRUE(std::filesystem::exists(dir_ / "S/station.json")) << "no kill came after the start";
  const Result<CaptureSummary> s = Capture(rig, true, Short(6));
  ASSERT_TRUE(s.ok()) << s.error();
  const Result<StationManifest> done = ValidateStation(dir_ / "S", {.require_complete = true});
  ASSERT_TRUE(done.ok()) << done.error();
  EXPECT_EQ(done->pairs.size(), 6u);
}

// A slope: the uphill view's terrain rises out of the top of the image, so the capture takes a
// pose above it, next. The capture is killed as soon as the uphill pair is stored: the plan
// with its upper pose was committed with it, and resume takes exactly what is missing.
TEST_F(CaptureTest, TerrainAboveAViewAddsAPoseAboveAndAKillThereIsResumed) {
  sim::SimStationOptions options;
  options.scene = "slope";
  options.seed = 1;
  const std::shared_ptr<const sim::SimStation> slope = *sim::BuildSimStation(options);
  Serve(15158, {}, slope);
  // A calibrated rig: the simulator's true calibration in place of the design values.
  ASSERT_TRUE(SaveCalibrationYaml(slope->rig.truth, dir_ / "calibration.yaml").ok());
  const std::string rig_file = WriteRig();
  {
    std::ifstream in(rig_file);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    text.erase(text.find("\ncalibration:\n") + 1);
    std::ofstream(rig_file) << text << "calibration_file: calibration.yaml\n";
  }
  const std::string out = dir_ / "S";
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Two azimuths: pan 0 looks uphill on this slope, pan 180 down.
    const char* argv[] = {TS_TOPOSTATION_EXE, "capture",    "--rig", rig_file.c_str(), "--out",
                          out.c_str(),        "--azimuths", "2",     "--exposure-us",  "7000",
                          "--json",           nullptr};
    ::execv(argv[0], const_cast<char**>(argv));
    ::_exit(127);
  }
  std::optional<StationManifest> partial;
  for (int i = 0; i < 3000 && !partial; ++i) {  // up to a minute
    std::this_thread::sleep_for(20ms);
    const Result<StationManifest> m = LoadStationManifest(out);
    if (m && m->plan.size() > 2) partial = *m;
    if (m && m->pairs.size() > 1) break;  // too late: the pose above was not planned
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  ASSERT_TRUE(partial) << "the uphill view did not ask for a pose above";
  ASSERT_EQ(partial->plan.size(), 3u);
  ASSERT_EQ(partial->pairs.size(), 1u);
  EXPECT_EQ(partial->pairs[0].index, 0);
  const StagePose planned = partial->plan[2];
  EXPECT_DOUBLE_EQ(planned.pan_deg, partial->plan[0].pan_deg);
  EXPECT_GT(planned.tilt_deg, partial->plan[0].tilt_deg + 20.0);
  ASSERT_TRUE(ValidateStation(out).ok());

  CaptureOptions o = Short(2);
  o.initial_exposure_us = 7000;
  const Result<CaptureSummary> second = Capture(rig_file, true, o);
  ASSERT_TRUE(second.ok()) << second.error();
  EXPECT_EQ(second->already_present, 1);
  EXPECT_EQ(second->captured_now, 2);  // the pose above and the downhill one; nothing twice
  const Result<StationManifest> done = ValidateStation(out, {.require_complete = true});
  ASSERT_TRUE(done.ok()) << done.error();
  ASSERT_EQ(done->plan.size(), 3u);
  EXPECT_DOUBLE_EQ(done->plan[2].tilt_deg, planned.tilt_deg);
  EXPECT_NEAR(done->FindPair(2)->readback.tilt_deg, planned.tilt_deg, 0.05);
  EXPECT_EQ(done->FindPair(0)->left.sha256, partial->pairs[0].left.sha256);
}

TEST_F(CaptureTest, OverexposedStartIsRetakenWithBothCamerasOnOneExposure) {
  Serve(15158);
  CaptureOptions o = Short(2);
  o.initial_exposure_us = 60000;  // far too long: the ground clips
  const Result<CaptureSummary> s = Capture(WriteRig(), false, o);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_GT(s->retakes, 0);
  EXPECT_LT(s->exposure_us, 30000);
  const Result<StationManifest> m = ValidateStation(dir_ / "S", {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  for (const PairRecord& p : m->pairs) {
    EXPECT_DOUBLE_EQ(p.exposure_us, s->exposure_us);
    for (const ImageRecord* r : {&p.left, &p.right}) {
      const Result<cv::Mat> image =
          ReadMonoPng(dir_ / ("S/" + r->file), PixelFormat::kMono8, 1392, 1040);
      ASSERT_TRUE(image.ok());
      const ExposureVerdict v = JudgeExposure(*image, *image, p.exposure_us, o.exposure);
      EXPECT_TRUE(v.ok) << r->file << ": " << v.reason << " mean " << v.mean;
    }
  }
}

TEST_F(CaptureTest, RefusesToOverwriteAStationAndResumeOfACompleteOneDoesNothing) {
  Serve(15156);
  const std::string rig = WriteRig();
  ASSERT_TRUE(Capture(rig, false, Short(2)).ok());
  const Result<CaptureSummary> again = Capture(rig, false, Short(2));
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.error().find("already holds a station"), std::string::npos);
  const Result<CaptureSummary> resume = Capture(rig, true, Short(2));
  ASSERT_TRUE(resume.ok()) << resume.error();
  EXPECT_EQ(resume->captured_now, 0);
}

// The camera backend against an independent GigE Vision implementation: Aravis's stock
// fake camera program.
TEST(StockFakeCamera, CameraBackendGrabsATriggeredFrame) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execlp("arv-fake-gv-camera-0.8", "arv-fake-gv-camera-0.8", "-i", "127.0.0.2", "-s",
             "GV-STOCK", nullptr);
    ::_exit(127);
  }
  std::this_thread::sleep_for(800ms);
  auto camera = OpenAravisCamera({"GV-STOCK", 0});
  ASSERT_TRUE(camera.ok()) << camera.error();
  CameraSettings settings;
  settings.width_px = 512;
  settings.height_px = 512;
  ASSERT_TRUE((*camera)->Configure(settings).ok());
  ASSERT_TRUE((*camera)->Start().ok());
  Result<Frame> frame = Error{""};
  for (int attempt = 0; attempt < 3 && !frame; ++attempt) {
    ASSERT_TRUE((*camera)->Trigger().ok());
    frame = (*camera)->WaitFrame(3000ms);
  }
  ASSERT_TRUE(frame.ok()) << frame.error();
  EXPECT_EQ(frame->image.cols, 512);
  EXPECT_EQ(frame->image.rows, 512);
  double min_value, max_value;
  cv::minMaxLoc(frame->image, &min_value, &max_value);
  EXPECT_GT(max_value, min_value);  // the fake camera's test pattern, not an empty buffer
  EXPECT_TRUE((*camera)->Stop().ok());
  camera->reset();
  ::kill(pid, SIGTERM);
  ::waitpid(pid, nullptr, 0);
}

}  // namespace
}  // namespace ts
