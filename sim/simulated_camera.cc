#include "sim/simulated_camera.h"

#include <arv.h>

#include <cmath>
#include <cstring>

namespace ts::sim {
namespace {

// Poses closer than a microdegree render the same view.
SimulatedCamera::ViewKey MakeViewKey(const StagePose& pose, int view) {
  return {std::llround(pose.pan_deg * 1e6), std::llround(pose.tilt_deg * 1e6), view};
}

// Views rendered ahead and not pre-rendered: the one the stage is coming to, and the last.
constexpr size_t kUnpinnedViews = 2;

void FillCallback(ArvBuffer* buffer, void* self, guint32 exposure_us, guint32 gain,
                  ArvPixelFormat pixel_format) {
  static_cast<SimulatedCamera*>(self)->FillBuffer(buffer, exposure_us, gain, pixel_format);
}

}  // namespace

SimulatedCamera::SimulatedCamera(std::shared_ptr<const SimStation> station,
                                 std::function<StagePose()> stage_pose,
                                 const SimulatedCameraOptions& options)
    : station_(std::move(station)),
      stage_pose_(std::move(stage_pose)),
      options_(options),
      renderer_(station_->scene, station_->mesh) {
  render_ahead_thread_ = std::thread([this] { RenderAheadLoop(); });
}

SimulatedCamera::~SimulatedCamera() {
  Stop();
  {
    std::lock_guard lock(cache_mutex_);
    quit_ = true;
  }
  cache_changed_.notify_all();
  render_ahead_thread_.join();
}

Status SimulatedCamera::Start() {
  std::lock_guard lock(camera_mutex_);
  if (camera_) return {};
  const bool lossy = options_.gvsp_loss_ratio > 0.0;
  const std::string& listen = lossy ? options_.hidden_address : options_.address;
  ArvGvFakeCamera* camera = arv_gv_fake_camera_new(listen.c_str(), options_.serial.c_str());
  if (!camera || !arv_gv_fake_camera_is_running(camera)) {
    if (camera) g_object_unref(camera);
    return Error{"simulated camera " + options_.serial + ": cannot serve on " + listen +
                 " (is it an address of this host's loopback?)"};
  }
  ArvFakeCamera* fake = arv_gv_fake_camera_get_fake_camera(camera);
  if (lossy) {
    // Clients must find it, and talk to it, on the public address: the relay's.
    GInetAddress* public_address = g_inet_address_new_from_string(options_.address.c_str());
    arv_fake_camera_set_inet_address(fake, public_address);
    g_object_unref(public_address);
    auto relay = GvspLossRelay::Start(options_.address, options_.hidden_address,
                                      options_.gvsp_loss_ratio, station_->scene.seed);
    if (!relay) {
      g_object_unref(camera);
      return Error{relay.error()};
    }
    relay_ = std::move(*relay);
  }
  const CameraIntrinsics& c = station_->rig.truth.rig.left;
  // The fake sensor is 2048 x 2048 by default; make it the rig's sensor.
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_SENSOR_WIDTH,
                                 static_cast<guint32>(c.width_px));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_SENSOR_HEIGHT,
                                 static_cast<guint32>(c.height_px));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_WIDTH,
                                 static_cast<guint32>(c.width_px));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_HEIGHT,
                                 static_cast<guint32>(c.height_px));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US, 8000);
#if ARAVIS_CHECK_VERSION(0, 9, 1)
  arv_fake_camera_set_fill_pattern(fake, FillCallback, this, nullptr);
#else
  arv_fake_camera_set_fill_pattern(fake, FillCallback, this);
#endif
  camera_ = camera;
  return {};
}

void SimulatedCamera::Stop() {
  ArvGvFakeCamera* camera;
  {
    std::lock_guard lock(camera_mutex_);
    camera = camera_;
    camera_ = nullptr;
  }
  if (camera) g_object_unref(camera);  // joins the camera thread and closes its sockets
  relay_.reset();
}

bool SimulatedCamera::running() const {
  std::lock_guard lock(camera_mutex_);
  return camera_ != nullptr;
}

void SimulatedCamera::RenderAhead(const StagePose& pose, int view) {
  {
    std::lock_guard lock(cache_mutex_);
    ahead_wanted_ = true;
    ahead_pose_ = pose;
    ahead_view_ = view;
  }
  cache_changed_.notify_all();
}

void SimulatedCamera::Prerender(const std::vector<StagePose>& poses) {
  for (const StagePose& pose : poses) Radiance(pose, 0, true);
}

bool SimulatedCamera::HasView(const StagePose& pose) const {
  const ViewKey key = MakeViewKey(pose, 0);
  std::lock_guard lock(cache_mutex_);
  return last_rendered_ahead_ == key || radiance_.count(key) > 0;
}

SimulatedCamera::Counters SimulatedCamera::counters() const {
  std::lock_guard lock(cache_mutex_);
  return counters_;
}

void SimulatedCamera::RenderAheadLoop() {
  std::unique_lock lock(cache_mutex_);
  while (true) {
    cache_changed_.wait(lock, [&] { return quit_ || ahead_wanted_; });
    if (quit_) return;
    ahead_wanted_ = false;
    const StagePose pose = ahead_pose_;
    const int view = ahead_view_;
    lock.unlock();
    Radiance(pose, view, false);
    lock.lock();
    last_rendered_ahead_ = MakeViewKey(pose, view);
  }
}

cv::Mat SimulatedCamera::Radiance(const StagePose& pose, int view, bool pin, bool* waited) {
  const ViewKey key = MakeViewKey(pose, view);
  auto cached = [&]() -> cv::Mat {
    std::lock_guard lock(cache_mutex_);
    const auto it = radiance_.find(key);
    if (it == radiance_.end()) return cv::Mat();
    if (pin) std::erase(unpinned_, key);
    return it->second;
  };
  if (cv::Mat r = cached(); !r.empty()) return r;
  if (waited) *waited = true;
  std::lock_guard render_lock(render_mutex_);
  if (cv::Mat r = cached(); !r.empty()) return r;  // rendered meanwhile by another thread
  FrameRequest request;
  request.side = options_.side;
  request.pan_deg = pose.pan_deg;
  request.tilt_deg = pose.tilt_deg;
  request.render = options_.render;
  cv::Mat radiance = options_.target_radiance ? options_.target_radiance(pose, view)
                                              : RenderRadiance(renderer_, *station_, request);
  std::lock_guard lock(cache_mutex_);
  radiance_[key] = radiance;
  if (!pin) {
    unpinned_.push_back(key);
    if (unpinned_.size() > kUnpinnedViews) {
      radiance_.erase(unpinned_.front());
      unpinned_.pop_front();
    }
  }
  return radiance;
}

cv::Mat SimulatedCamera::Frame(const StagePose& pose, unsigned exposure_us, unsigned gain_db,
                               PixelFormat format) {
  int view = 0;
  FrameKey key;
  {
    std::lock_guard lock(cache_mutex_);
    if (options_.target_radiance) view = counters_.frames % options_.target_views;
    ++counters_.frames;
    key = {MakeViewKey(pose, view), exposure_us, gain_db, static_cast<int>(format)};
    if (!frame_.empty() && frame_key_ == key) return frame_;
  }
  bool waited = false;
  const cv::Mat radiance = Radiance(pose, view, false, &waited);
  if (options_.target_views > 1) RenderAhead(pose, (view + 1) % options_.target_views);
  FrameRequest request;
  request.side = options_.side;
  request.pan_deg = pose.pan_deg;
  request.tilt_deg = pose.tilt_deg;
  request.view = view;
  request.exposure_us = exposure_us;
  request.gain_db = gain_db;
  request.format = format;
  cv::Mat frame = ExposeFrame(*station_, request, radiance);
  std::lock_guard lock(cache_mutex_);
  counters_.waited_for_render += waited ? 1 : 0;
  frame_key_ = key;
  frame_ = frame;
  return frame;
}

void SimulatedCamera::FillBuffer(void* buffer_ptr, unsigned exposure_us, unsigned gain,
                                 unsigned pixel_format) {
  SimulatedCamera* self = this;
  ArvBuffer* buffer = static_cast<ArvBuffer*>(buffer_ptr);
  size_t size = 0;
  auto* data = static_cast<uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, &size)));
  gint x = 0, y = 0, width = 0, height = 0;
  arv_buffer_get_image_region(buffer, &x, &y, &width, &height);
  const bool mono16 = pixel_format == ARV_PIXEL_FORMAT_MONO_16;
  const size_t bytes_per_pixel = mono16 ? 2 : 1;
  // Aravis 0.8 reports a size of 0 inside the callback; the buffer holds the full payload.
  const size_t bytes = static_cast<size_t>(width) * height * bytes_per_pixel;
  if (!data || width <= 0 || height <= 0) return;
  if (pixel_format != ARV_PIXEL_FORMAT_MONO_8 && !mono16) {
    std::memset(data, 0, bytes);  // only Mono8 and Mono16 are simulated
    return;
  }
  const PixelFormat format = mono16 ? PixelFormat::kMono16 : PixelFormat::kMono8;
  const cv::Mat frame = self->Frame(self->stage_pose_(), exposure_us, gain, format);
  for (int row = 0; row < height; ++row) {
    uint8_t* out = data + static_cast<size_t>(row) * width * bytes_per_pixel;
    const int source_row = y + row;
    if (source_row < 0 || source_row >= frame.rows) {
      std::memset(out, 0, static_cast<size_t>(width) * bytes_per_pixel);
      continue;
    }
    const int columns = std::clamp(frame.cols - x, 0, width);
    std::memcpy(out, frame.ptr<uint8_t>(source_row) + static_cast<size_t>(x) * bytes_per_pixel,
                static_cast<size_t>(columns) * bytes_per_pixel);
    std::memset(out + static_cast<size_t>(columns) * bytes_per_pixel, 0,
                static_cast<size_t>(width - columns) * bytes_per_pixel);
  }
}

}  // namespace ts::sim
