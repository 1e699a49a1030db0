#pragma once
// config/sim-rig.yaml with the stage at another endpoint (a port of a test's own, or Modbus
// RTU on the simulated stage's pseudo-terminal), written to `file`.
#include <fstream>
#include <iterator>
#include <string>

namespace ts::testing {

// stage: a flow map, e.g. "{transport: tcp, host: 127.0.0.1, port: 15150}".
inline std::string WriteSimRigConfig(const std::string& file, const std::string& stage) {
  std::ifstream in(TS_SOURCE_DIR "/config/sim-rig.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string tcp = "{transport: tcp, host: 127.0.0.1, port: 15020, unit_id: 1}";
  text.replace(text.find(tcp), tcp.size(), stage);
  std::ofstream(file) << text;
  return file;
}

inline std::string TcpStage(int port) {
  return "{transport: tcp, host: 127.0.0.1, port: " + std::to_string(port) + "}";
}

}  // namespace ts::testing
