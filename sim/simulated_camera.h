#pragma once
// A simulated GigE Vision camera: Aravis's ArvGvFakeCamera on its own address, with a fill
// callback that renders what this camera of the rig sees at the stage's current pose, at
// the exposure, gain and pixel format the client set. Honours software trigger (the fake
// camera's own GenICam model). When the stage settles, the frame for the new pose is
// rendered in the background, so a trigger is answered from the cache within milliseconds.
//
// Threads: the fill callback runs on Aravis's camera thread; PoseChanged() on the stage's;
// Start()/Stop() from the owner. All are safe together.
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <thread>
#include <tuple>

#include "core/exposure.h"
#include "core/result.h"
#include "sim/gvsp_loss_relay.h"
#include "sim/sim_station.h"

struct _ArvGvFakeCamera;

namespace ts::sim {

struct SimulatedCameraOptions {
  std::string address = "127.0.0.1";
  std::string serial = "TS-SIM-L";
  Side side = Side::kLeft;
  double gvsp_loss_ratio = 0.0;  // fault gvsp-loss: fraction of GVSP packets lost
  // With gvsp-loss the fake camera listens here and a GvspLossRelay stands on `address`
  // (the fake camera cannot resend; the relay can). Must be an address of lo.
  std::string hidden_address = "127.0.0.11";
  RenderOptions render;
};

class SimulatedCamera {
 public:
  SimulatedCamera(std::shared_ptr<const SimStation> station, std::function<StagePose()> stage_pose,
                  const SimulatedCameraOptions& options);
  ~SimulatedCamera();
  SimulatedCamera(const SimulatedCamera&) = delete;
  SimulatedCamera& operator=(const SimulatedCamera&) = delete;

  // Brings the camera onto the network (again); error if the address cannot be used.
  Status Start();
  // Takes the camera off the network (the camera-gone fault).
  void Stop();
  bool running() const;
  // The stage came to rest at `pose`: render the next frame ahead of the trigger.
  void PoseChanged(const StagePose& pose);
  const SimulatedCameraOptions& options() const { return options_; }

  // Aravis's fill callback lands here (on the camera thread): buffer is an ArvBuffer*.
  void FillBuffer(void* buffer, unsigned exposure_us, unsigned gain, unsigned pixel_format);

  using Key = std::tuple<long long, long long, unsigned, unsigned, int>;

 private:
  cv::Mat Frame(const StagePose& pose, unsigned exposure_us, unsigned gain_db, PixelFormat format);
  void PrerenderLoop();

  std::shared_ptr<const SimStation> station_;
  std::function<StagePose()> stage_pose_;
  SimulatedCameraOptions options_;
  mutable std::mutex camera_mutex_;
  _ArvGvFakeCamera* camera_ = nullptr;
  std::unique_ptr<GvspLossRelay> relay_;

  std::mutex render_mutex_;  // one render at a time per camera (one Renderer)
  Renderer renderer_;
  std::mutex cache_mutex_;
  std::condition_variable cache_changed_;
  Key cached_key_{};
  cv::Mat cached_;
  bool prerender_wanted_ = false;
  StagePose prerender_pose_;
  unsigned last_exposure_us_ = static_cast<unsigned>(kDefaultExposureUs), last_gain_ = 0;
  PixelFormat last_format_ = PixelFormat::kMono8;
  bool quit_ = false;
  std::thread prerender_thread_;
};

}  // namespace ts::sim
