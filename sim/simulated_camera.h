#pragma once
// A simulated GigE Vision camera: Aravis's ArvGvFakeCamera on its own address, with a fill
// callback that renders what this camera of the rig sees at the stage's current pose, at
// the exposure, gain and pixel format the client set. Honours software trigger (the fake
// camera's own GenICam model). The costly part of a frame, the scene's radiance at a pose, is
// rendered ahead: while the stage moves to a pose (RenderAhead), or for all the poses of a
// capture before it starts (Prerender); a trigger then costs only the sensor's exposure.
//
// Threads: the fill callback runs on Aravis's camera thread; RenderAhead() on the stage's;
// Start()/Stop()/Prerender() from the owner. All are safe together.
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

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
  // Calibration targets instead of the scene (`sim serve --calibration`): the radiance of
  // view `view` at a stage pose. The camera's n-th frame shows view n % target_views: a
  // board the helper moves after every pair (both cameras are triggered for every pair), or a
  // control field's one view.
  std::function<cv::Mat(const StagePose&, int view)> target_radiance;
  int target_views = 1;
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
  // The stage will come to rest at `pose`: render its view now, before the trigger. (Targets
  // of many views: the next view is rendered ahead after each frame.)
  void RenderAhead(const StagePose& pose, int view = 0);
  // Whether the view at `pose` is rendered: a trigger there costs only the exposure.
  bool HasView(const StagePose& pose) const;
  // Renders the views at these poses now (blocking) and keeps them for the camera's life.
  void Prerender(const std::vector<StagePose>& poses);
  struct Counters {
    int frames = 0;             // frames served
    int waited_for_render = 0;  // of them, triggered before their view was rendered
  };
  Counters counters() const;
  const SimulatedCameraOptions& options() const { return options_; }

  // Aravis's fill callback lands here (on the camera thread): buffer is an ArvBuffer*.
  void FillBuffer(void* buffer, unsigned exposure_us, unsigned gain, unsigned pixel_format);

  using ViewKey = std::tuple<long long, long long, int>;  // pan, tilt (microdegrees), view
  using FrameKey = std::tuple<ViewKey, unsigned, unsigned, int>;

 private:
  cv::Mat Frame(const StagePose& pose, unsigned exposure_us, unsigned gain_db, PixelFormat format);
  // The radiance of a view at `pose`, from the cache or rendered now; *waited is set when it
  // was not in the cache (rendered now, or still being rendered ahead).
  cv::Mat Radiance(const StagePose& pose, int view, bool pin, bool* waited = nullptr);
  void RenderAheadLoop();

  std::shared_ptr<const SimStation> station_;
  std::function<StagePose()> stage_pose_;
  SimulatedCameraOptions options_;
  mutable std::mutex camera_mutex_;
  _ArvGvFakeCamera* camera_ = nullptr;
  std::unique_ptr<GvspLossRelay> relay_;

  std::mutex render_mutex_;  // one render at a time per camera (one Renderer)
  Renderer renderer_;
  mutable std::mutex cache_mutex_;
  std::condition_variable cache_changed_;
  std::map<ViewKey, cv::Mat> radiance_;  // pre-rendered (pinned) and the latest rendered ahead
  std::deque<ViewKey> unpinned_;         // oldest first
  FrameKey frame_key_{};
  cv::Mat frame_;  // the last frame served
  Counters counters_;
  bool ahead_wanted_ = false;
  StagePose ahead_pose_;
  int ahead_view_ = 0;
  ViewKey last_rendered_ahead_{-1, -1, -1};
  bool quit_ = false;
  std::thread render_ahead_thread_;
};

}  // namespace ts::sim
