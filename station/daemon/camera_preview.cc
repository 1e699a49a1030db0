#include "station/daemon/camera_preview.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "devices/aravis_camera.h"

namespace ts::daemon {

std::vector<unsigned char> EncodePreview(const cv::Mat& frame, int max_width_px) {
  cv::Mat image = frame;
  if (image.depth() == CV_16U) image.convertTo(image, CV_8U, 1.0 / 256.0);
  if (image.cols > max_width_px) {
    const double scale = static_cast<double>(max_width_px) / image.cols;
    cv::resize(image, image, {}, scale, scale, cv::INTER_AREA);
  }
  std::vector<unsigned char> jpeg;
  cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 80});
  return jpeg;
}

Result<cv::Mat> CameraPreview::Grab(Side side) {
  std::string holder;
  std::unique_ptr<RigLease> lease =
      devices_->TryLease("a camera preview", &holder, DeviceSupervisor::LeaseKind::kPreview);
  if (!lease) return Error{"the rig is in use (" + holder + ")"};
  const RigConfig& rig = devices_->rig();
  auto camera = OpenAravisCamera(side == Side::kLeft ? rig.left_camera : rig.right_camera);
  if (!camera) return Error{camera.error()};
  CameraSettings settings;
  const CameraIntrinsics& model =
      side == Side::kLeft ? rig.calibration.rig.left : rig.calibration.rig.right;
  settings.width_px = model.width_px;
  settings.height_px = model.height_px;
  if (Status s = (*camera)->Configure(settings); !s) return Error{s.error()};
  if (Status s = (*camera)->Start(); !s) return Error{s.error()};
  Result<Frame> frame = Error{"no frame"};
  for (int attempt = 0; attempt < 2 && !frame; ++attempt) {  // the first trigger may be lost
    if (Status s = (*camera)->Trigger(); !s) return Error{s.error()};
    frame = (*camera)->WaitFrame(std::chrono::milliseconds(3000));
  }
  if (Status s = (*camera)->Stop(); !s && frame) return Error{s.error()};
  if (!frame) return Error{frame.error()};
  return frame->image;
}

Result<std::vector<unsigned char>> CameraPreview::Snapshot(Side side) {
  const cv::Mat captured = jobs_->LastFrame(side);
  Cached& c = cached_[side == Side::kLeft ? 0 : 1];
  const auto now = std::chrono::steady_clock::now();
  {
    std::lock_guard lock(cache_mutex_);
    if (!captured.empty()) {  // encoded once per frame the capture takes
      if (c.frame.data != captured.data) c = {EncodePreview(captured, kMaxWidthPx), now, captured};
      return c.jpeg;
    }
    if (!c.jpeg.empty() && now - c.at < kReuseFor) return c.jpeg;
  }
  std::unique_lock grab(grab_mutex_, std::try_to_lock);
  if (!grab.owns_lock()) {  // a frame is being taken: the last one, rather than a queue
    std::lock_guard lock(cache_mutex_);
    if (!c.jpeg.empty()) return c.jpeg;
    return Error{"a preview is being taken; ask again in a second"};
  }
  Result<cv::Mat> frame = Grab(side);
  if (!frame) return Error{frame.error()};
  std::lock_guard lock(cache_mutex_);
  c = {EncodePreview(*frame, kMaxWidthPx), now, {}};
  return c.jpeg;
}

}  // namespace ts::daemon
