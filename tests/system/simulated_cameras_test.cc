// Aravis clients grab software-triggered frames from the simulated GigE Vision cameras over
// loopback (127.0.0.1 and 127.0.0.2; run inside scripts/netns-run), and the frames are the
// offline render of the same pose, pixel for pixel. Faults: GVSP loss and a camera that goes.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "devices/aravis_camera.h"
#include "devices/modbus_stage.h"
#include "sim/sim_server.h"

namespace ts::sim {
namespace {

class SimulatedCameras : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SimStationOptions options;
    options.scene = "hills";
    options.seed = 2;
    station_ = *BuildSimStation(options);
  }
  static cv::Mat Offline(Side side, const StagePose& pose, double exposure_us, PixelFormat format,
                         double gain_db = 0.0) {
    Renderer renderer(station_->scene, station_->mesh);
    FrameRequest r;
    r.side = side;
    r.pan_deg = pose.pan_deg;
    r.tilt_deg = pose.tilt_deg;
    r.exposure_us = exposure_us;
    r.gain_db = gain_db;
    r.format = format;
    return RenderFrame(renderer, *station_, r);
  }
  static SimServeOptions Options(int port) {
    SimServeOptions o;
    o.stage_port = port;
    o.stage_pty = false;
    return o;
  }
  // The appliance's own camera backend, opened by serial and started.
  static Result<std::unique_ptr<Camera>> Started(const std::string& serial, PixelFormat format,
                                                 double exposure_us, double gain_db = 0.0) {
    auto camera = OpenAravisCamera({serial, 0});
    if (!camera) return camera;
    CameraSettings settings;
    settings.width_px = 1392;
    settings.height_px = 1040;
    settings.format = format;
    settings.exposure_us = exposure_us;
    settings.gain_db = gain_db;
    if (Status s = (*camera)->Configure(settings); !s) return Error{s.error()};
    if (Status s = (*camera)->Start(); !s) return Error{s.error()};
    return camera;
  }
  // A software-triggered frame; the first trigger after start may be lost: retried.
  static Result<Frame> Grab(Camera& camera) {
    Result<Frame> frame = Error{"no frame"};
    for (int attempt = 0; attempt < 3 && !frame; ++attempt) {
      if (Status s = camera.Trigger(); !s) return Error{s.error()};
      frame = camera.WaitFrame(std::chrono::milliseconds(8000));
    }
    return frame;
  }
  static std::shared_ptr<const SimStation> station_;
};
std::shared_ptr<const SimStation> SimulatedCameras::station_;

TEST_F(SimulatedCameras, TriggeredFramesEqualTheOfflineRender) {
  auto server = SimServer::Start(station_, Options(15130));
  ASSERT_TRUE(server.ok()) << server.error();
  const StagePose pose = (*server)->stage().Pose();
  for (const auto& [side, serial] :
       {std::pair{Side::kLeft, "TS-SIM-L"}, std::pair{Side::kRight, "TS-SIM-R"}}) {
    auto camera = Started(serial, PixelFormat::kMono8, 5000);
    ASSERT_TRUE(camera.ok()) << camera.error();
    const Result<Frame> grab = Grab(**camera);
    ASSERT_TRUE(grab.ok()) << grab.error();
    const cv::Mat expected = Offline(side, pose, 5000, PixelFormat::kMono8);
    ASSERT_EQ(grab->image.size(), expected.size());
    EXPECT_EQ(cv::norm(grab->image, expected, cv::NORM_INF), 0.0) << serial;
    EXPECT_GT(cv::mean(grab->image)[0], 20.0);  // a real scene, not a blank buffer
  }
}

// `sim serve --prerender`: the views of the given targets are rendered before the server
// starts; a frame there is served without waiting for a render, and is still the offline
// render of the pose where the stage really came to rest.
TEST_F(SimulatedCameras, PrerenderedPosesAreServedAtOnceAndEqualTheOfflineRender) {
  SimServeOptions o = Options(15135);
  const StagePose target{60.0, -12.3456789};  // finer than the target register's millidegree
  o.prerender_targets = {target, {90.0, -12.0}};
  auto server = SimServer::Start(station_, o);
  ASSERT_TRUE(server.ok()) << server.error();
  StageEndpoint endpoint;
  endpoint.port = 15135;
  auto stage = OpenModbusStage(endpoint);
  ASSERT_TRUE(stage.ok()) << stage.error();
  ASSERT_TRUE((*stage)->Home(std::chrono::milliseconds(30000)).ok());
  const Result<StagePose> at = (*stage)->MoveTo(target, 0.05, std::chrono::milliseconds(20000));
  ASSERT_TRUE(at.ok()) << at.error();
  const StagePose rest = (*server)->stage().Pose();
  const StagePose predicted = (*server)->stage().RestingPose(target);
  EXPECT_EQ(rest.pan_deg, predicted.pan_deg);
  EXPECT_EQ(rest.tilt_deg, predicted.tilt_deg);
  const MoveTiming timing = (*stage)->last_move_timing();
  EXPECT_GT(timing.moving_s, 0.3);  // 12 deg of tilt at 30 deg/s, and 60 deg of pan
  EXPECT_NEAR(timing.settling_s, 0.2, 0.1);
  auto camera = Started("TS-SIM-L", PixelFormat::kMono8, 5000);
  ASSERT_TRUE(camera.ok()) << camera.error();
  const Result<Frame> grab = Grab(**camera);
  ASSERT_TRUE(grab.ok()) << grab.error();
  EXPECT_EQ(
      cv::norm(grab->image, Offline(Side::kLeft, rest, 5000, PixelFormat::kMono8), cv::NORM_INF),
      0.0);
  const SimulatedCamera::Counters c = (*server)->camera(Side::kLeft).counters();
  EXPECT_GE(c.frames, 1);
  EXPECT_EQ(c.waited_for_render, 0);
}

// A move comes to rest in position only once both cameras have rendered its view, however
// long the render takes beside the move: a trigger then never waits for a render (which would
// run in the thread that answers the camera's control channel). A short move against a slow
// render (supersampling 8: seconds per view) would otherwise trigger first.
TEST_F(SimulatedCameras, AMoveIsInPositionOnlyOnceBothCamerasHaveItsView) {
  SimServeOptions o = Options(15136);
  o.render.supersampling = 8;
  auto server = SimServer::Start(station_, o);
  ASSERT_TRUE(server.ok()) << server.error();
  StageEndpoint endpoint;
  endpoint.port = 15136;
  auto stage = OpenModbusStage(endpoint);
  ASSERT_TRUE(stage.ok()) << stage.error();
  ASSERT_TRUE((*stage)->Home(std::chrono::milliseconds(30000)).ok());
  const auto t0 = std::chrono::steady_clock::now();
  const Result<StagePose> at = (*stage)->MoveTo({1.0, 0.0}, 0.05, std::chrono::milliseconds(20000));
  ASSERT_TRUE(at.ok()) << at.error();
  const double move_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const StagePose rest = (*server)->stage().Pose();
  for (Side side : {Side::kLeft, Side::kRight})
    EXPECT_TRUE((*server)->camera(side).HasView(rest)) << "in position after " << move_s << " s";
  auto camera = Started("TS-SIM-R", PixelFormat::kMono8, 5000);
  ASSERT_TRUE(camera.ok()) << camera.error();
  const Result<Frame> grab = Grab(**camera);
  ASSERT_TRUE(grab.ok()) << grab.error();
  const SimulatedCamera::Counters c = (*server)->camera(Side::kRight).counters();
  EXPECT_GE(c.frames, 1);
  EXPECT_EQ(c.waited_for_render, 0);
  std::printf("1 deg of pan with its view rendered: %.2f s\n", move_s);
}

// A frame that began before the trigger we wait for is an earlier one, arrived late: dropped.
// Frame B is triggered and left in the stream; the next wait, after trigger C, must return C.
TEST_F(SimulatedCameras, AFrameOlderThanItsTriggerIsDropped) {
  auto server = SimServer::Start(station_, Options(15134));
  ASSERT_TRUE(server.ok()) << server.error();
  auto camera = Started("TS-SIM-L", PixelFormat::kMono8, 5000);
  ASSERT_TRUE(camera.ok()) << camera.error();
  const Result<Frame> a = Grab(**camera);
  ASSERT_TRUE(a.ok()) << a.error();
  ASSERT_TRUE((*camera)->Trigger().ok());  // B, never waited for
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  ASSERT_TRUE((*camera)->Trigger().ok());  // C
  const Result<Frame> c = (*camera)->WaitFrame(std::chrono::milliseconds(8000));
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->frame_id, a->frame_id + 2) << "the late frame B was taken for C";
}

// The fake camera's gain is the integer GainRaw (0-10); the simulator reads it as dB.
TEST_F(SimulatedCameras, Mono16ExposureAndGainAreHonoured) {
  auto server = SimServer::Start(station_, Options(15131));
  ASSERT_TRUE(server.ok()) << server.error();
  const StagePose pose = (*server)->stage().Pose();
  auto camera = Started("TS-SIM-L", PixelFormat::kMono16, 800, 6);
  ASSERT_TRUE(camera.ok()) << camera.error();
  const Result<Frame> grab = Grab(**camera);
  ASSERT_TRUE(grab.ok()) << grab.error();
  const cv::Mat expected = Offline(Side::kLeft, pose, 800, PixelFormat::kMono16, 6);
  EXPECT_EQ(cv::norm(grab->image, expected, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::mean(expected)[0],
            1.5 * cv::mean(Offline(Side::kLeft, pose, 800, PixelFormat::kMono16, 0))[0]);
}

// GVSP loss on the link: packets are lost at the requested ratio and, as from a real camera,
// sent again on request (Aravis's fake camera cannot resend; the relay in front of it does).
TEST_F(SimulatedCameras, PacketLossIsRecoveredByResend) {
  SimServeOptions options = Options(15132);
  options.faults.gvsp_loss = 0.02;
  auto server = SimServer::Start(station_, options);
  ASSERT_TRUE(server.ok()) << server.error();
  const StagePose pose = (*server)->stage().Pose();
  auto camera = Started("TS-SIM-R", PixelFormat::kMono8, 5000);
  ASSERT_TRUE(camera.ok()) << camera.error();
  const Result<Frame> grab = Grab(**camera);
  ASSERT_TRUE(grab.ok()) << grab.error();
  EXPECT_GT(grab->statistics.resent_packets, 0u);  // lost and asked for again
  EXPECT_EQ(
      cv::norm(grab->image, Offline(Side::kRight, pose, 5000, PixelFormat::kMono8), cv::NORM_INF),
      0.0);
}

TEST_F(SimulatedCameras, CameraGoneLeavesTheNetworkAndComesBack) {
  SimServeOptions options = Options(15133);
  options.faults.camera_gone = CameraGoneFault{Side::kRight, 1.0, 3.0};
  auto server = SimServer::Start(station_, options);
  ASSERT_TRUE(server.ok()) << server.error();
  std::this_thread::sleep_for(std::chrono::milliseconds(1800));
  EXPECT_FALSE((*server)->camera(Side::kRight).running());
  EXPECT_FALSE(OpenAravisCamera({"TS-SIM-R", 0}).ok());  // not discovered
  EXPECT_TRUE(OpenAravisCamera({"TS-SIM-L", 0}).ok());   // the other one stays
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  EXPECT_TRUE((*server)->camera(Side::kRight).running());
  auto camera = Started("TS-SIM-R", PixelFormat::kMono8, 5000);
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_TRUE(Grab(**camera).ok());
}

}  // namespace
}  // namespace ts::sim
