#pragma once
// A machine-vision camera, as the acquisition layer sees it. One implementation talks GigE
// Vision / USB3 Vision through Aravis (aravis_camera.h).
//
// Lifecycle: open (backend factory) -> Configure() -> Start() -> {Trigger(), WaitFrame()}...
// -> Stop(). After a lost control channel, Reconnect() re-opens and re-applies the settings.
// Every call returns a Status/Result; none throws. Not thread-safe: one owner thread (two
// cameras may be driven from two threads).
#include <chrono>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "core/exposure.h"
#include "core/options.h"
#include "core/pixel_format.h"
#include "core/result.h"

namespace ts {

struct CameraSettings {
  int width_px = 0;   // 0: the sensor's full width
  int height_px = 0;  // 0: the sensor's full height
  PixelFormat format = PixelFormat::kMono8;
  double exposure_us = kDefaultExposureUs;
  double gain_db = 0.0;
  bool hardware_trigger = false;
  int packet_size_bytes = 0;
  int stream_buffers = 4;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("width_px", self.width_px, {"image width (0: the sensor's)", "px", 0, 65535});
    v("height_px", self.height_px, {"image height (0: the sensor's)", "px", 0, 65535});
    v("format", self.format, {"pixel format (0 Mono8, 1 Mono16)"});
    v("exposure_us", self.exposure_us, {"exposure", "us", 1, 1e7});
    v("gain_db", self.gain_db, {"gain", "dB", 0, 48});
    v("hardware_trigger", self.hardware_trigger, {"Line1 rising edge instead of software trigger"});
    v("packet_size_bytes", self.packet_size_bytes,
      {"GigE Vision packet size (0: negotiate)", "bytes", 0, 16384});
    v("stream_buffers", self.stream_buffers, {"stream buffers", "", 4, 64});
  }
  bool Check(std::string* why) const;
};

struct FrameStatistics {
  uint64_t resent_packets = 0;   // packets asked for again and received, for this frame
  uint64_t missing_packets = 0;  // packets never received, for this frame
};

struct Frame {
  cv::Mat image;  // CV_8UC1 or CV_16UC1, owned
  uint64_t frame_id = 0;
  int64_t timestamp_ns = 0;  // camera timestamp
  double exposure_us = 0.0;
  double gain_db = 0.0;
  FrameStatistics statistics;
};

class Camera {
 public:
  virtual ~Camera() = default;
  virtual std::string Describe() const = 0;  // "camera TS-SIM-L (127.0.0.1)"
  virtual Status Configure(const CameraSettings& settings) = 0;
  virtual Status Start() = 0;
  virtual Status Stop() = 0;
  // Exposure and gain while running (the capture locks both cameras to the same values).
  virtual Status SetExposure(double exposure_us, double gain_db) = 0;
  virtual Status Trigger() = 0;
  // The next complete frame; an error for a timeout or an incomplete frame (named).
  virtual Result<Frame> WaitFrame(std::chrono::milliseconds timeout) = 0;
  virtual bool ControlLost() const = 0;
  virtual Status Reconnect(std::chrono::milliseconds timeout) = 0;
};

}  // namespace ts
