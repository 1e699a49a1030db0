#pragma once
// The daemon's config (topostationd --config FILE.yaml):
//
//   schema_version: 1
//   rig_file: rig.yaml                 # the rig (devices, calibration); relative to this file
//   state_dir: /var/lib/topostationd   # the job history (jobs.sqlite) and the token
//   stations_dir: stations             # relative to state_dir unless absolute
//   listen: {address: 127.0.0.1, port: 8080}
//   allowed_hosts: [topostation.local] # Host names beside localhost and the listen address
//   token_file: token                  # relative to state_dir (default: state_dir/token)
//   device_poll_s: 2
//   usb: {stage: "0403:6001", left_camera: "1ab2:0001:SERIAL"}   # optional: USB presence
//   headless:                          # optional
//     mode: off | when_ready | schedule
//     station_pattern: "site-{n}"      # {n} the next free number, {utc} 20261125T193000Z
//     line: L1
//     instrument_height_m: 1.5
//     every_hours: 6                   # schedule only
//
// Every error names the file and the field.
#include <map>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts::daemon {

enum class HeadlessMode { kOff, kWhenReady, kSchedule };

struct HeadlessSettings {
  HeadlessMode mode = HeadlessMode::kOff;
  std::string station_pattern = "station-{n}";
  std::string line;
  double instrument_height_m = 1.5;
  double every_hours = 6.0;
};

struct DaemonConfig {
  std::string file;
  std::string rig_file;  // absolute or relative to the working directory
  std::string state_dir;
  std::string stations_dir;
  std::string listen_address = "127.0.0.1";
  int listen_port = 8080;
  std::vector<std::string> allowed_hosts;  // besides localhost and listen_address
  std::string token_file;
  double device_poll_s = 2.0;
  // Device name (left_camera, right_camera, stage) -> "VID:PID[:SERIAL]" of its USB device
  // (a USB3 Vision camera, the stage's USB-serial adapter), watched by libusb hotplug.
  std::map<std::string, std::string> usb;
  HeadlessSettings headless;

  std::string JobDatabase() const { return state_dir + "/jobs.sqlite"; }
};

Result<DaemonConfig> LoadDaemonConfig(const std::string& file);

// The station id of a headless capture: the pattern with {n} the lowest number not yet a
// station in `stations_dir`, {utc} the time. The result passes IsStationId or is an error.
Result<std::string> NextStationId(const std::string& pattern, const std::string& stations_dir);

// [A-Za-z0-9_-]{1,64}: the only text from a request that may become part of a path.
bool IsStationId(const std::string& id);

}  // namespace ts::daemon
