#include "devices/aravis_camera.h"

#include <arv.h>

#include <atomic>
#include <cstring>
#include <thread>

namespace ts {

bool CameraSettings::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (packet_size_bytes == 0 || packet_size_bytes >= 576) return true;
  if (why) *why = "packet_size_bytes must be 0 or in [576, 16384]";
  return false;
}

namespace {

constexpr std::chrono::milliseconds kArmTime{150};
constexpr std::chrono::milliseconds kControlWait{8000};

std::string Text(const char* s) { return s ? s : ""; }

std::string TakeError(GError** error) {
  std::string message = *error ? (*error)->message : "unknown error";
  g_clear_error(error);
  return message;
}

// Finds the Aravis device id for a serial number or an address.
std::string FindDeviceId(const std::string& wanted) {
  arv_update_device_list();
  for (unsigned i = 0; i < arv_get_n_devices(); ++i) {
    if (Text(arv_get_device_serial_nbr(i)) == wanted || Text(arv_get_device_address(i)) == wanted ||
        Text(arv_get_device_id(i)) == wanted)
      return Text(arv_get_device_id(i));
  }
  return "";
}

class AravisCamera : public Camera {
 public:
  explicit AravisCamera(const CameraEndpoint& endpoint) : endpoint_(endpoint) {}
  ~AravisCamera() override { Close(); }

  Status Open() {
    const std::string id = FindDeviceId(endpoint_.id);
    if (id.empty()) return Error{Describe() + ": not found on the network or bus"};
    GError* error = nullptr;
    camera_ = arv_camera_new(id.c_str(), &error);
    if (!camera_) return Error{Describe() + ": cannot open: " + TakeError(&error)};
    if (Status s = TakeControl(); !s) {
      g_object_unref(camera_);
      camera_ = nullptr;
      return s;
    }
    control_lost_ = false;
    g_signal_connect(arv_camera_get_device(camera_), "control-lost", G_CALLBACK(OnControlLost),
                     this);
    return {};
  }

  std::string Describe() const override { return "camera " + endpoint_.id; }

  // A GigE Vision device obeys one controller. After a controller dies (kill -9, power) the
  // device keeps serving it until its heartbeat times out (typically 3 s), ignoring every
  // write of a newcomer, stream destination included: wait for control, or fail clearly.
  Status TakeControl() {
    if (!arv_camera_is_gv_device(camera_)) return {};
    ArvGvDevice* device = ARV_GV_DEVICE(arv_camera_get_device(camera_));
    const auto deadline = std::chrono::steady_clock::now() + kControlWait;
    while (!arv_gv_device_is_controller(device)) {
      if (std::chrono::steady_clock::now() > deadline)
        return Error{Describe() + ": another application controls it (still after " +
                     std::to_string(kControlWait.count()) + " ms)"};
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      GError* error = nullptr;
      arv_gv_device_take_control(device, &error);
      g_clear_error(&error);
    }
    return {};
  }

  Status Configure(const CameraSettings& settings) override {
    std::string why;
    if (!settings.Check(&why)) return Error{Describe() + ": " + why};
    settings_ = settings;
    configured_ = true;
    return Apply();
  }

  Status Start() override {
    if (!camera_) return Error{Describe() + ": not open"};
    if (stream_) return {};
    GError* error = nullptr;
    stream_ = arv_camera_create_stream(camera_, nullptr, nullptr, &error);
    if (!stream_) return Error{Describe() + ": cannot create stream: " + TakeError(&error)};
    const size_t payload = arv_camera_get_payload(camera_, &error);
    if (error) return Error{Describe() + ": " + TakeError(&error)};
    if (ARV_IS_GV_STREAM(stream_)) {
      // Room for three frames, not Aravis's "auto" (one payload): the kernel charges each
      // datagram's overhead too, so a one-payload buffer overflows within a frame whenever
      // the receiving thread is held up for a moment, and a device that cannot resend (as
      // Aravis's own fake camera) then loses the frame. The kernel caps it at rmem_max.
      g_object_set(stream_, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED,
                   "socket-buffer-size", static_cast<gint>(3 * payload), "packet-resend",
                   ARV_GV_STREAM_PACKET_RESEND_ALWAYS, nullptr);
    }
    for (int i = 0; i < settings_.stream_buffers; ++i)
      arv_stream_push_buffer(stream_, arv_buffer_new(payload, nullptr));
    arv_camera_start_acquisition(camera_, &error);
    if (error) return Error{Describe() + ": cannot start acquisition: " + TakeError(&error)};
    last_resent_ = last_missing_ = 0;
    // A trigger right after AcquisitionStart can be lost (the device has not armed yet).
    std::this_thread::sleep_for(kArmTime);
    return {};
  }

  Status Stop() override {
    if (camera_ && stream_) {
      GError* error = nullptr;
      arv_camera_stop_acquisition(camera_, &error);
      g_clear_error(&error);  // best effort: the camera may be gone
    }
    if (stream_) g_object_unref(stream_);
    stream_ = nullptr;
    return {};
  }

  Status SetExposure(double exposure_us, double gain_db) override {
    settings_.exposure_us = exposure_us;
    settings_.gain_db = gain_db;
    GError* error = nullptr;
    arv_camera_set_exposure_time(camera_, exposure_us, &error);
    if (!error) arv_camera_set_gain(camera_, gain_db, &error);
    if (error) return Error{Describe() + ": cannot set exposure: " + TakeError(&error)};
    return {};
  }

  Status Trigger() override {
    if (!camera_ || !stream_) return Error{Describe() + ": not started"};
    // Frames that began before this moment belong to an earlier trigger (late ones) or to
    // none (the free frame some devices send at AcquisitionStart): WaitFrame drops them. The
    // clock is the one Aravis stamps a buffer with at its first packet (g_get_real_time).
    triggered_at_ns_ = static_cast<guint64>(g_get_real_time()) * 1000;
    if (settings_.hardware_trigger) return {};
    GError* error = nullptr;
    arv_camera_software_trigger(camera_, &error);
    if (error) return Error{Describe() + ": software trigger failed: " + TakeError(&error)};
    return {};
  }

  Result<Frame> WaitFrame(std::chrono::milliseconds timeout) override {
    if (!stream_) return Error{Describe() + ": not started"};
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    ArvBuffer* buffer = nullptr;
    while (!buffer) {
      const auto left = std::chrono::duration_cast<std::chrono::microseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;
      buffer = arv_stream_timeout_pop_buffer(stream_, static_cast<guint64>(left.count()));
      // A frame whose first packet arrived before the trigger belongs to something earlier
      // (a late frame, or the free frame some devices send at AcquisitionStart).
      if (buffer && arv_buffer_get_system_timestamp(buffer) < triggered_at_ns_) {
        arv_stream_push_buffer(stream_, buffer);
        buffer = nullptr;
      }
    }
    if (!buffer)
      return Error{Describe() + ": no frame within " + std::to_string(timeout.count()) + " ms" +
                   (control_lost_ ? " (control channel lost)" : "")};
    Frame frame;
    const ArvBufferStatus status = arv_buffer_get_status(buffer);
    if (ARV_IS_GV_STREAM(stream_)) {
      guint64 resent = 0, missing = 0;
      arv_gv_stream_get_statistics(ARV_GV_STREAM(stream_), &resent, &missing);
      frame.statistics = {resent - last_resent_, missing - last_missing_};
      last_resent_ = resent;
      last_missing_ = missing;
    }
    Result<Frame> result = Error{""};
    if (status != ARV_BUFFER_STATUS_SUCCESS) {
      result = Error{Describe() + ": incomplete frame (" + StatusName(status) + ", " +
                     std::to_string(frame.statistics.missing_packets) + " packets missing)"};
    } else {
      result = Copy(buffer, frame);
    }
    arv_stream_push_buffer(stream_, buffer);  // every buffer goes back, whatever its state
    return result;
  }

  bool ControlLost() const override { return control_lost_; }

  Status Reconnect(std::chrono::milliseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    Status last = Error{Describe() + ": reconnect not attempted"};
    do {
      Close();
      last = Open();
      if (last && configured_) last = Apply();
      if (last) last = Start();
      if (last) return {};
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    } while (std::chrono::steady_clock::now() < deadline);
    return last;
  }

 private:
  static void OnControlLost(ArvDevice*, gpointer self) {
    static_cast<AravisCamera*>(self)->control_lost_ = true;  // Aravis's heartbeat thread
  }

  static std::string StatusName(ArvBufferStatus s) {
    switch (s) {
      case ARV_BUFFER_STATUS_TIMEOUT:
        return "timeout";
      case ARV_BUFFER_STATUS_MISSING_PACKETS:
        return "missing packets";
      case ARV_BUFFER_STATUS_WRONG_PACKET_ID:
        return "wrong packet id";
      case ARV_BUFFER_STATUS_SIZE_MISMATCH:
        return "size mismatch";
      case ARV_BUFFER_STATUS_ABORTED:
        return "aborted";
      default:
        return "status " + std::to_string(static_cast<int>(s));
    }
  }

  Result<Frame> Copy(ArvBuffer* buffer, Frame frame) {
    size_t size = 0;
    const void* data = arv_buffer_get_data(buffer, &size);
    const int width = arv_buffer_get_image_width(buffer);
    const int height = arv_buffer_get_image_height(buffer);
    const ArvPixelFormat format = arv_buffer_get_image_pixel_format(buffer);
    const bool mono16 = format == ARV_PIXEL_FORMAT_MONO_16;
    if (format != ARV_PIXEL_FORMAT_MONO_8 && !mono16)
      return Error{Describe() + ": unexpected pixel format 0x" + std::to_string(format)};
    const size_t expected = static_cast<size_t>(width) * height * (mono16 ? 2 : 1);
    if (!data || size < expected || width <= 0 || height <= 0)
      return Error{Describe() + ": frame of " + std::to_string(size) + " bytes, expected " +
                   std::to_string(expected)};
    frame.image =
        cv::Mat(height, width, mono16 ? CV_16UC1 : CV_8UC1, const_cast<void*>(data)).clone();
    frame.frame_id = arv_buffer_get_frame_id(buffer);
    frame.timestamp_ns = static_cast<int64_t>(arv_buffer_get_timestamp(buffer));
    frame.exposure_us = settings_.exposure_us;
    frame.gain_db = settings_.gain_db;
    return frame;
  }

  Status Apply() {
    if (!camera_) return Error{Describe() + ": not open"};
    GError* error = nullptr;
    // A controller that died (kill -9, power) leaves the camera streaming to its old port;
    // stopping first makes the device forget that destination.
    arv_camera_stop_acquisition(camera_, &error);
    g_clear_error(&error);
    if (arv_camera_is_gv_device(camera_)) {
      // As root Aravis reads GVSP through packet sockets, which never see loopback traffic.
      arv_camera_gv_set_stream_options(camera_, ARV_GV_STREAM_OPTION_PACKET_SOCKET_DISABLED);
      if (settings_.packet_size_bytes > 0)
        arv_camera_gv_set_packet_size(camera_, settings_.packet_size_bytes, &error);
      if (error) return Error{Describe() + ": packet size: " + TakeError(&error)};
    }
    gint x, y, width, height;
    arv_camera_get_sensor_size(camera_, &width, &height, &error);
    if (error) return Error{Describe() + ": sensor size: " + TakeError(&error)};
    if (settings_.width_px > 0) width = settings_.width_px;
    if (settings_.height_px > 0) height = settings_.height_px;
    x = y = 0;
    arv_camera_set_region(camera_, x, y, width, height, &error);
    if (!error)
      arv_camera_set_pixel_format(camera_,
                                  settings_.format == PixelFormat::kMono16
                                      ? ARV_PIXEL_FORMAT_MONO_16
                                      : ARV_PIXEL_FORMAT_MONO_8,
                                  &error);
    if (!error) arv_camera_set_exposure_time(camera_, settings_.exposure_us, &error);
    if (!error) arv_camera_set_gain(camera_, settings_.gain_db, &error);
    if (!error) {
      if (settings_.hardware_trigger)
        arv_camera_set_trigger(camera_, "Line1", &error);
      else
        arv_camera_set_trigger(camera_, "Software", &error);
    }
    if (error) return Error{Describe() + ": cannot configure: " + TakeError(&error)};
    gint got_x, got_y, got_w, got_h;
    arv_camera_get_region(camera_, &got_x, &got_y, &got_w, &got_h, &error);
    if (error) return Error{Describe() + ": " + TakeError(&error)};
    if (got_w != width || got_h != height)
      return Error{Describe() + ": asked for " + std::to_string(width) + "x" +
                   std::to_string(height) + ", camera gives " + std::to_string(got_w) + "x" +
                   std::to_string(got_h)};
    return {};
  }

  void Close() {
    if (Status s = Stop(); !s) {
    }
    if (camera_) g_object_unref(camera_);
    camera_ = nullptr;
  }

  CameraEndpoint endpoint_;
  CameraSettings settings_;
  bool configured_ = false;
  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  std::atomic<bool> control_lost_{false};
  guint64 last_resent_ = 0, last_missing_ = 0;
  guint64 triggered_at_ns_ = 0;  // host time of the last trigger
};

}  // namespace

std::vector<CameraInfo> ListAravisCameras() {
  arv_update_device_list();
  std::vector<CameraInfo> cameras;
  for (unsigned i = 0; i < arv_get_n_devices(); ++i) {
    cameras.push_back({Text(arv_get_device_id(i)), Text(arv_get_device_serial_nbr(i)),
                       Text(arv_get_device_address(i)), Text(arv_get_device_vendor(i)),
                       Text(arv_get_device_model(i)), Text(arv_get_device_protocol(i))});
  }
  return cameras;
}

Result<std::unique_ptr<Camera>> OpenAravisCamera(const CameraEndpoint& endpoint) {
  std::string why;
  if (!endpoint.Check(&why)) return Error{"camera: " + why};
  auto camera = std::make_unique<AravisCamera>(endpoint);
  if (Status s = camera->Open(); !s) return Error{s.error()};
  return std::unique_ptr<Camera>(std::move(camera));
}

}  // namespace ts
