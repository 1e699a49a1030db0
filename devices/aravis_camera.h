#pragma once
// Cameras through Aravis 0.8: GigE Vision (and USB3 Vision) devices found by discovery and
// opened by serial number or IP address. GigE streams use the auto socket buffer and packet
// resend; packet sockets are disabled (they never see loopback, where the simulator lives).
#include <memory>
#include <string>
#include <vector>

#include "devices/camera.h"
#include "devices/endpoints.h"

namespace ts {

struct CameraInfo {
  std::string id;  // Aravis device id
  std::string serial;
  std::string address;  // IP for GigE Vision, bus path for USB3 Vision
  std::string vendor;
  std::string model;
  std::string protocol;  // "GigEVision", "USB3Vision", "Fake"
};

// Cameras Aravis can see now (runs discovery).
std::vector<CameraInfo> ListAravisCameras();
Result<std::unique_ptr<Camera>> OpenAravisCamera(const CameraEndpoint& endpoint);

}  // namespace ts
