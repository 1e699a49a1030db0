// Aravis clients grab software-triggered frames from the simulated GigE Vision cameras over
// loopback (127.0.0.1 and 127.0.0.2; run inside scripts/netns-run), and the frames are the
// offline render of the same pose, pixel for pixel. Faults: GVSP loss and a camera that goes.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "sim/sim_server.h"
#include "tests/system/aravis_test_client.h"

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
  static std::shared_ptr<const SimStation> station_;
};
std::shared_ptr<const SimStation> SimulatedCameras::station_;

TEST_F(SimulatedCameras, TriggeredFramesEqualTheOfflineRender) {
  auto server = SimServer::Start(station_, Options(15130));
  ASSERT_TRUE(server.ok()) << server.error();
  const StagePose pose = (*server)->stage().Pose();
  for (const auto& [side, serial] :
       {std::pair{Side::kLeft, "TS-SIM-L"}, std::pair{Side::kRight, "TS-SIM-R"}}) {
    testing::AravisTestClient client(serial);
    ASSERT_TRUE(client.ok()) << serial << " not discovered";
    ASSERT_TRUE(client.Start(1392, 1040, ARV_PIXEL_FORMAT_MONO_8, 5000));
    const testing::Grab grab = client.TriggerAndGrab();
    ASSERT_EQ(grab.status, ARV_BUFFER_STATUS_SUCCESS) << serial;
    const cv::Mat expected = Offline(side, pose, 5000, PixelFormat::kMono8);
    ASSERT_EQ(grab.image.size(), expected.size());
    EXPECT_EQ(cv::norm(grab.image, expected, cv::NORM_INF), 0.0) << serial;
    EXPECT_GT(cv::mean(grab.image)[0], 20.0);  // a real scene, not a blank buffer
  }
}

// The fake camera's gain is the integer GainRaw (0-10); the simulator reads it as dB.
TEST_F(SimulatedCameras, Mono16ExposureAndGainAreHonoured) {
  auto server = SimServer::Start(station_, Options(15131));
  ASSERT_TRUE(server.ok()) << server.error();
  const StagePose pose = (*server)->stage().Pose();
  testing::AravisTestClient client("TS-SIM-L");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(client.Start(1392, 1040, ARV_PIXEL_FORMAT_MONO_16, 2500));
  const testing::Grab grab = client.TriggerAndGrab();
  ASSERT_EQ(grab.status, ARV_BUFFER_STATUS_SUCCESS);
  EXPECT_EQ(
      cv::norm(grab.image, Offline(Side::kLeft, pose, 2500, PixelFormat::kMono16), cv::NORM_INF),
      0.0);
}

// GVSP loss on the link: packets are lost at the requested ratio and, as from a real camera,
// sent again on request (Aravis's fake camera cannot resend; the relay in front of it does).
TEST_F(SimulatedCameras, PacketLossIsRecoveredByResend) {
  SimServeOptions options = Options(15132);
  options.faults.gvsp_loss = 0.02;
  auto server = SimServer::Start(station_, options);
  ASSERT_TRUE(server.ok()) << server.error();
  const StagePose pose = (*server)->stage().Pose();
  testing::AravisTestClient client("TS-SIM-R");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(client.Start(1392, 1040, ARV_PIXEL_FORMAT_MONO_8, 5000));
  const testing::Grab grab = client.TriggerAndGrab();
  ASSERT_EQ(grab.status, ARV_BUFFER_STATUS_SUCCESS);
  EXPECT_GT(grab.resent_packets, 0u);  // lost and asked for again
  EXPECT_EQ(
      cv::norm(grab.image, Offline(Side::kRight, pose, 5000, PixelFormat::kMono8), cv::NORM_INF),
      0.0);
}

TEST_F(SimulatedCameras, CameraGoneLeavesTheNetworkAndComesBack) {
  SimServeOptions options = Options(15133);
  options.faults.camera_gone = CameraGoneFault{Side::kRight, 1.0, 3.0};
  auto server = SimServer::Start(station_, options);
  ASSERT_TRUE(server.ok()) << server.error();
  std::this_thread::sleep_for(std::chrono::milliseconds(1800));
  EXPECT_FALSE((*server)->camera(Side::kRight).running());
  EXPECT_FALSE(testing::AravisTestClient("TS-SIM-R").ok());  // not discovered
  EXPECT_TRUE(testing::AravisTestClient("TS-SIM-L").ok());   // the other one stays
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  EXPECT_TRUE((*server)->camera(Side::kRight).running());
  testing::AravisTestClient client("TS-SIM-R");
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(client.Start(1392, 1040, ARV_PIXEL_FORMAT_MONO_8, 5000));
  EXPECT_EQ(client.TriggerAndGrab().status, ARV_BUFFER_STATUS_SUCCESS);
}

}  // namespace
}  // namespace ts::sim
