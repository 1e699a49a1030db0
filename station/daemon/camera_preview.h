#pragma once
// GET /cameras/{side}/snapshot.jpg: one frame from a camera, downscaled, as JPEG. While a job
// captures, the camera is not touched: the preview is the last frame that job took. A frame
// is reused for a second, so that many clients polling the preview do not each trigger the
// camera.
#include <chrono>
#include <mutex>
#include <string>
#include <vector>

#include "core/result.h"
#include "station/daemon/device_supervisor.h"
#include "station/daemon/job_runner.h"

namespace ts::daemon {

class CameraPreview {
 public:
  static constexpr int kMaxWidthPx = 800;
  static constexpr std::chrono::milliseconds kReuseFor{1000};
  CameraPreview(DeviceSupervisor* devices, JobRunner* jobs) : devices_(devices), jobs_(jobs) {}
  // JPEG bytes, or an error with the reason (the rig in use and no frame yet, a camera lost).
  Result<std::vector<unsigned char>> Snapshot(Side side);

 private:
  Result<cv::Mat> Grab(Side side);
  DeviceSupervisor* devices_;
  JobRunner* jobs_;
  std::mutex grab_mutex_;   // one frame taken at a time
  std::mutex cache_mutex_;  // guards cached_
  struct Cached {
    std::vector<unsigned char> jpeg;
    std::chrono::steady_clock::time_point at{};
    cv::Mat frame;  // the capture's frame it was encoded from, if any
  } cached_[2];
};

// A frame as a JPEG no wider than max_width_px (16-bit frames scaled to 8 bits).
std::vector<unsigned char> EncodePreview(const cv::Mat& frame, int max_width_px);

}  // namespace ts::daemon
