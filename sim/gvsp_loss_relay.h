#pragma once
// The gvsp-loss fault as a lossy link in front of a simulated camera. Aravis's fake camera
// drops GVSP packets itself but never answers PACKETRESEND, so a lost packet loses the frame;
// a real camera resends. This relay stands on the camera's public address while the fake
// camera listens on a hidden one (advertising the public address in its discovery data):
//   GVCP from the client is forwarded to the camera, except PACKETRESEND, which the relay
//   answers itself; the stream destination the client writes (SCDA/SCP) is recorded and
//   replaced by the relay's own GVSP port.
//   GVSP from the camera is forwarded to the client, each packet lost with the given ratio,
//   and the last frames are kept so that requested packets can be sent again.
// One client at a time (the capture); threads: one, owned by the relay.
#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "core/result.h"

namespace ts::sim {

class GvspLossRelay {
 public:
  static Result<std::unique_ptr<GvspLossRelay>> Start(const std::string& public_address,
                                                      const std::string& camera_address,
                                                      double loss_ratio, uint64_t seed);
  ~GvspLossRelay();
  uint64_t dropped() const { return dropped_; }
  uint64_t resent() const { return resent_; }

 private:
  GvspLossRelay() = default;
  void Loop();

  int gvcp_fd_ = -1;      // public_address:3956, faces the client
  int upstream_fd_ = -1;  // talks to camera_address:3956
  int gvsp_fd_ = -1;      // where the camera streams to
  uint32_t camera_ip_ = 0;
  double loss_ratio_ = 0.0;
  uint64_t rng_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> dropped_{0}, resent_{0};
  std::thread thread_;
};

}  // namespace ts::sim
