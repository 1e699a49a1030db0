#include "sim/faults.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

namespace ts::sim {
namespace {

std::vector<std::string> Split(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

// "0.05" -> 0.05; throws std::invalid_argument with a message.
double Number(const std::string& key, const std::string& text, double min, double max) {
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(v) || v < min || v > max) {
    std::ostringstream m;
    m << key << ": '" << text << "' must be a number in [" << min << ", " << max << "]";
    throw std::invalid_argument(m.str());
  }
  return v;
}

// "right:after=5:for=10" -> head "right" and {after: 5, for: 10}; only `allowed` keys.
std::pair<std::string, std::map<std::string, std::string>> Parts(
    const std::string& key, const std::string& value, const std::vector<std::string>& allowed) {
  const std::vector<std::string> parts = Split(value, ':');
  if (parts.empty()) throw std::invalid_argument(key + ": missing value");
  std::map<std::string, std::string> fields;
  for (size_t i = 1; i < parts.size(); ++i) {
    const size_t eq = parts[i].find('=');
    const std::string name = parts[i].substr(0, eq);
    if (eq == std::string::npos || std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw std::invalid_argument(key + ": unknown part '" + parts[i] + "'");
    fields[name] = parts[i].substr(eq + 1);
  }
  for (const std::string& name : allowed)
    if (!fields.count(name)) throw std::invalid_argument(key + ": missing '" + name + "='");
  return {parts[0], fields};
}

AxisFault ParseAxisFault(const std::string& key, const std::string& value) {
  const auto [axis, fields] = Parts(key, value, {"after"});
  if (axis != "pan" && axis != "tilt")
    throw std::invalid_argument(key + ": axis must be pan or tilt, got '" + axis + "'");
  return {axis == "pan", static_cast<int>(Number(key + " after", fields.at("after"), 0, 1e6))};
}

}  // namespace

Result<SimFaults> ParseFaults(const std::string& spec) {
  SimFaults faults;
  try {
    for (const std::string& item : Split(spec, ',')) {
      if (item.empty()) continue;
      const size_t eq = item.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("'" + item + "' is not key=value");
      const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
      if (key == "gvsp-loss") {
        faults.gvsp_loss = Number(key, value, 0.0, 0.5);
      } else if (key == "modbus-crc") {
        faults.modbus_crc = Number(key, value, 0.0, 0.9);
      } else if (key == "modbus-drop") {
        faults.modbus_drop = Number(key, value, 0.0, 0.9);
      } else if (key == "camera-gone") {
        const auto [side, fields] = Parts(key, value, {"after", "for"});
        if (side != "left" && side != "right")
          throw std::invalid_argument(key + ": side must be left or right, got '" + side + "'");
        faults.camera_gone = CameraGoneFault{side == "left" ? Side::kLeft : Side::kRight,
                                             Number(key + " after", fields.at("after"), 0, 1e6),
                                             Number(key + " for", fields.at("for"), 0, 1e6)};
      } else if (key == "stage-stall") {
        faults.stage_stall = ParseAxisFault(key, value);
      } else if (key == "stage-alarm") {
        faults.stage_alarm = ParseAxisFault(key, value);
      } else {
        throw std::invalid_argument(
            "unknown fault '" + key +
            "' (gvsp-loss, camera-gone, stage-stall, stage-alarm, modbus-crc, modbus-drop)");
      }
    }
  } catch (const std::invalid_argument& e) {
    return Error{std::string("--faults: ") + e.what()};
  }
  return faults;
}

}  // namespace ts::sim
