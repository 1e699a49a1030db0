#pragma once
// A minimal Aravis client for the simulator's system tests: find a camera by serial through
// discovery, configure it, software-trigger and grab one frame. (The appliance's own camera
// backend lives in devices/; these tests check the simulated cameras themselves.)
#include <arv.h>

#include <chrono>
#include <opencv2/core.hpp>
#include <string>
#include <thread>

namespace ts::testing {

struct Grab {
  cv::Mat image;
  ArvBufferStatus status = ARV_BUFFER_STATUS_UNKNOWN;
  guint64 resent_packets = 0;
  guint64 missing_packets = 0;
};

class AravisTestClient {
 public:
  // Opens the camera whose serial number discovery reports; ok() is false if none does.
  explicit AravisTestClient(const std::string& serial) {
    arv_update_device_list();
    for (unsigned i = 0; i < arv_get_n_devices(); ++i) {
      const char* s = arv_get_device_serial_nbr(i);
      if (s && serial == s) camera_ = arv_camera_new(arv_get_device_id(i), nullptr);
    }
  }
  ~AravisTestClient() {
    if (stream_) {
      arv_camera_stop_acquisition(camera_, nullptr);
      g_object_unref(stream_);
    }
    if (camera_) g_object_unref(camera_);
  }
  bool ok() const { return camera_ != nullptr; }

  bool Start(int width, int height, ArvPixelFormat format, double exposure_us, double gain = 0.0) {
    GError* error = nullptr;
    // As root Aravis would read GVSP through packet sockets, which never see loopback.
    arv_camera_gv_set_stream_options(camera_, ARV_GV_STREAM_OPTION_PACKET_SOCKET_DISABLED);
    arv_camera_set_region(camera_, 0, 0, width, height, &error);
    if (!error) arv_camera_set_pixel_format(camera_, format, &error);
    if (!error) arv_camera_set_exposure_time(camera_, exposure_us, &error);
    if (!error) arv_camera_set_gain(camera_, gain, &error);
    if (!error) arv_camera_set_trigger(camera_, "Software", &error);
    if (!error) stream_ = arv_camera_create_stream(camera_, nullptr, nullptr, &error);
    if (error) {
      g_clear_error(&error);
      return false;
    }
    g_object_set(stream_, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_AUTO, "packet-resend",
                 ARV_GV_STREAM_PACKET_RESEND_ALWAYS, nullptr);
    const size_t payload = arv_camera_get_payload(camera_, nullptr);
    for (int i = 0; i < 4; ++i) arv_stream_push_buffer(stream_, arv_buffer_new(payload, nullptr));
    arv_camera_start_acquisition(camera_, &error);
    format_ = format;
    return error == nullptr;
  }

  // Triggers and waits for a frame; the first trigger after start may be lost: retried.
  Grab TriggerAndGrab(int attempts = 3, guint64 timeout_us = 8000000) {
    Grab grab;
    for (int a = 0; a < attempts; ++a) {
      arv_camera_software_trigger(camera_, nullptr);
      ArvBuffer* buffer = arv_stream_timeout_pop_buffer(stream_, timeout_us);
      if (!buffer) continue;
      grab.status = arv_buffer_get_status(buffer);
      if (grab.status == ARV_BUFFER_STATUS_SUCCESS) {
        size_t size = 0;
        const void* data = arv_buffer_get_data(buffer, &size);
        const int type = format_ == ARV_PIXEL_FORMAT_MONO_16 ? CV_16UC1 : CV_8UC1;
        grab.image = cv::Mat(arv_buffer_get_image_height(buffer),
                             arv_buffer_get_image_width(buffer), type, const_cast<void*>(data))
                         .clone();
      }
      arv_stream_push_buffer(stream_, buffer);
      if (grab.status == ARV_BUFFER_STATUS_SUCCESS) break;
    }
    guint64 completed, failures, underruns;
    arv_stream_get_statistics(stream_, &completed, &failures, &underruns);
    if (ARV_IS_GV_STREAM(stream_))
      arv_gv_stream_get_statistics(ARV_GV_STREAM(stream_), &grab.resent_packets,
                                   &grab.missing_packets);
    return grab;
  }

 private:
  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  ArvPixelFormat format_ = ARV_PIXEL_FORMAT_MONO_8;
};

}  // namespace ts::testing
