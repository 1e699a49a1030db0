#include "devices/endpoints.h"

namespace ts {

bool CameraEndpoint::Check(std::string* why) const {
  std::string err;
  if (id.empty())
    err = "id (serial or address) is empty";
  else if (packet_size_bytes != 0 && (packet_size_bytes < 576 || packet_size_bytes > 16384))
    err = "packet_size_bytes must be 0 (negotiate) or in [576, 16384]";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

bool StageEndpoint::Check(std::string* why) const {
  std::string err;
  if (unit_id < 1 || unit_id > 247)
    err = "unit_id must be in [1, 247]";
  else if (transport == StageTransport::kTcp && (host.empty() || port < 1 || port > 65535))
    err = "TCP needs a host and a port in [1, 65535]";
  else if (transport == StageTransport::kRtu && device.empty())
    err = "RTU needs a device";
  else if (transport == StageTransport::kRtu && baud <= 0)
    err = "baud must be positive";
  else if (parity != 'N' && parity != 'E' && parity != 'O')
    err = "parity must be N, E or O";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

}  // namespace ts
