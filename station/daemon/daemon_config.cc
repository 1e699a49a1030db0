#include "station/daemon/daemon_config.h"

#include <ctime>
#include <filesystem>

#include "devices/usb_watcher.h"
#include "processing/io/yaml_map.h"

namespace ts::daemon {
namespace {

namespace fs = std::filesystem;

std::string Resolve(const fs::path& base, const std::string& path) {
  return fs::path(path).is_absolute() ? path : (base / path).lexically_normal().string();
}

HeadlessSettings ParseHeadless(YamlMap m) {
  HeadlessSettings h;
  const std::string mode = m.String("mode", "off");
  if (mode == "off")
    h.mode = HeadlessMode::kOff;
  else if (mode == "when_ready")
    h.mode = HeadlessMode::kWhenReady;
  else if (mode == "schedule")
    h.mode = HeadlessMode::kSchedule;
  else
    m.Fail("mode", "must be off, when_ready or schedule, got '" + mode + "'");
  h.station_pattern = m.String("station_pattern", h.station_pattern);
  if (h.station_pattern.find("{n}") == std::string::npos &&
      h.station_pattern.find("{utc}") == std::string::npos)
    m.Fail("station_pattern", "needs {n} or {utc}, so that each capture has a station of its own");
  h.line = m.String("line", "");
  h.instrument_height_m = m.Double("instrument_height_m", h.instrument_height_m);
  if (!(h.instrument_height_m > 0.0 && h.instrument_height_m <= 10.0))
    m.Fail("instrument_height_m", "must be within (0, 10] m");
  h.every_hours = m.Double("every_hours", h.every_hours);
  if (!(h.every_hours >= 0.01 && h.every_hours <= 24.0 * 366))
    m.Fail("every_hours", "must be within 0.01 h and a year");
  m.RejectUnknownKeys();
  return h;
}

}  // namespace

Result<DaemonConfig> LoadDaemonConfig(const std::string& file) {
  try {
    YamlMap root(LoadYamlFile(file), "");
    DaemonConfig c;
    c.file = file;
    const fs::path base = fs::absolute(file).parent_path();
    if (const int v = root.Int("schema_version", 0, 1000000); v != 1)
      root.Fail("schema_version", "unsupported version " + std::to_string(v));
    c.rig_file = Resolve(base, root.String("rig_file"));
    c.state_dir = Resolve(base, root.String("state_dir"));
    c.stations_dir = Resolve(c.state_dir, root.String("stations_dir", "stations"));
    c.token_file = Resolve(c.state_dir, root.String("token_file", "token"));
    if (root.Has("listen")) {
      YamlMap listen = root.Map("listen");
      c.listen_address = listen.String("address", c.listen_address);
      c.listen_port = listen.Int("port", 1, 65535, c.listen_port);
      listen.RejectUnknownKeys();
    }
    if (root.Has("allowed_hosts")) c.allowed_hosts = root.Strings("allowed_hosts");
    c.device_poll_s = root.Double("device_poll_s", c.device_poll_s);
    if (!(c.device_poll_s >= 0.1 && c.device_poll_s <= 600))
      root.Fail("device_poll_s", "must be within 0.1 and 600 s");
    if (root.Has("headless")) c.headless = ParseHeadless(root.Map("headless"));
    if (root.Has("usb")) {
      YamlMap usb = root.Map("usb");
      for (const char* name : {"left_camera", "right_camera", "stage"})
        if (usb.Has(name)) {
          c.usb[name] = usb.String(name);
          if (Result<UsbMatch> m = ParseUsbMatch(name, c.usb[name]); !m) usb.Fail(name, m.error());
        }
      usb.RejectUnknownKeys();
    }
    root.RejectUnknownKeys();
    return c;
  } catch (const ConfigError& e) {
    return Error{file + ": " + e.what()};
  }
}

bool IsStationId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (char ch : id)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_' && ch != '-') return false;
  return true;
}

Result<std::string> NextStationId(const std::string& pattern, const std::string& stations_dir) {
  auto fill = [&](int n) {
    std::string id = pattern;
    if (size_t at = id.find("{n}"); at != std::string::npos) id.replace(at, 3, std::to_string(n));
    if (size_t at = id.find("{utc}"); at != std::string::npos) {
      const std::time_t now = std::time(nullptr);
      std::tm utc{};
      gmtime_r(&now, &utc);
      char text[32];
      std::strftime(text, sizeof(text), "%Y%m%dT%H%M%SZ", &utc);
      id.replace(at, 5, text);
    }
    return id;
  };
  // Without {n} there is one id to try (two {utc} captures in one second: the second fails).
  const int last = pattern.find("{n}") == std::string::npos ? 1 : 999999;
  for (int n = 1; n <= last; ++n) {
    const std::string id = fill(n);
    if (!IsStationId(id))
      return Error{"headless.station_pattern '" + pattern + "' gives '" + id +
                   "', not a station id ([A-Za-z0-9_-]{1,64})"};
    if (!fs::exists(fs::path(stations_dir) / id)) return id;
  }
  return Error{"headless.station_pattern '" + pattern + "': no free station id"};
}

}  // namespace ts::daemon
