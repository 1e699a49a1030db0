#include "acquisition/rig_config.h"

#include <filesystem>

#include "processing/io/calibration_yaml.h"
#include "processing/io/yaml_map.h"

namespace ts {
namespace {

CameraEndpoint ParseCamera(YamlMap m) {
  CameraEndpoint c;
  c.id = m.String("id");
  c.packet_size_bytes = m.Int("packet_size_bytes", 0, 16384, 0);
  m.RejectUnknownKeys();
  std::string why;
  if (!c.Check(&why)) throw ConfigError(m.path() + ": " + why);
  return c;
}

StageEndpoint ParseStage(YamlMap m) {
  StageEndpoint s;
  const std::string transport = m.String("transport");
  if (transport == "tcp") {
    s.transport = StageTransport::kTcp;
    s.host = m.String("host");
    s.port = m.Int("port", 1, 65535);
  } else if (transport == "rtu") {
    s.transport = StageTransport::kRtu;
    s.device = m.String("device");
    s.baud = m.Int("baud", 1, 4000000, 115200);
    const std::string parity = m.String("parity", "N");
    if (parity != "N" && parity != "E" && parity != "O") m.Fail("parity", "must be N, E or O");
    s.parity = parity[0];
    s.rs485 = m.Bool("rs485", false);
  } else {
    m.Fail("transport", "must be tcp or rtu, got '" + transport + "'");
  }
  s.unit_id = m.Int("unit_id", 1, 247, 1);
  const std::string inclinometer = m.String("inclinometer", "pan");
  if (inclinometer != "pan" && inclinometer != "base")
    m.Fail("inclinometer",
           "must be pan (it turns with the pan) or base, got '" + inclinometer + "'");
  s.inclinometer_turns_with_pan = inclinometer == "pan";
  m.RejectUnknownKeys();
  return s;
}

}  // namespace

Result<RigConfig> LoadRigConfig(const std::string& file) {
  std::string error_file = file;
  try {
    YamlMap root(LoadYamlFile(file), "");
    RigConfig rig;
    rig.file = file;
    const int version = root.Int("schema_version", 0, 1000000);
    if (version != kRigConfigSchemaVersion)
      root.Fail("schema_version", "unsupported version " + std::to_string(version));
    rig.name = root.String("name");
    YamlMap devices = root.Map("devices");
    rig.left_camera = ParseCamera(devices.Map("left_camera"));
    rig.right_camera = ParseCamera(devices.Map("right_camera"));
    rig.stage = ParseStage(devices.Map("stage"));
    devices.RejectUnknownKeys();
    const bool inline_cal = root.Has("calibration"), external = root.Has("calibration_file");
    if (inline_cal == external)
      root.Fail("calibration", "give exactly one of calibration and calibration_file");
    if (inline_cal) {
      rig.calibration = ParseCalibration(root.Map("calibration"));
    } else {
      const std::filesystem::path cal_path =
          std::filesystem::path(file).parent_path() / root.String("calibration_file");
      Result<Calibration> cal = LoadCalibrationYaml(cal_path.string());
      if (!cal) return Error{cal.error()};
      rig.calibration = *cal;
    }
    root.RejectUnknownKeys();
    return rig;
  } catch (const ConfigError& e) {
    return Error{error_file + ": " + e.what()};
  }
}

}  // namespace ts
