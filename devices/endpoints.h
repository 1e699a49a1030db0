#pragma once
// Where the devices of a rig are found: plain values read from the rig config and handed to
// the backends. A camera is named by serial number or IP address (GigE Vision) or serial
// (USB3 Vision); the stage speaks Modbus TCP or Modbus RTU on a serial line.
#include <string>

namespace ts {

struct CameraEndpoint {
  std::string id;             // serial number (e.g. "TS-SIM-L") or IPv4 address
  int packet_size_bytes = 0;  // GVSP packet size; 0 = negotiate
  bool Check(std::string* why) const;
};

enum class StageTransport { kTcp, kRtu };

struct StageEndpoint {
  StageTransport transport = StageTransport::kTcp;
  std::string host = "127.0.0.1";  // TCP
  int port = 502;                  // TCP
  std::string device;              // RTU: serial device, e.g. /dev/topostation-stage
  int baud = 115200;               // RTU
  char parity = 'N';               // RTU: 'N', 'E' or 'O'
  bool rs485 = false;              // RTU: switch the line to RS-485 mode
  int unit_id = 1;                 // Modbus unit (slave) id
  // Where the device block's inclinometer sits: on the pan platform (it turns with the pan, so
  // readings round the circle cancel its index error: inclinometer.h), or on the base.
  bool inclinometer_turns_with_pan = true;
  bool Check(std::string* why) const;
};

}  // namespace ts
