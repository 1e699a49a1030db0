#include "station/daemon/calibrate_job.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "processing/io/calibration_yaml.h"
#include "station/child_process.h"

namespace ts::daemon {
namespace {

namespace fs = std::filesystem;

// topostation, installed beside topostationd (and built beside it).
std::string Topostation() {
  std::error_code ec;
  return (fs::read_symlink("/proc/self/exe", ec).parent_path() / "topostation").string();
}

std::string LastLine(const std::string& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace

Result<nlohmann::json> CalibrateRigInChild(const std::vector<std::string>& station_dirs,
                                           const Calibration& start, bool refine_cameras,
                                           const std::string& out_yaml,
                                           const std::function<bool()>& should_stop) {
  std::error_code ec;
  fs::create_directories(fs::path(out_yaml).parent_path(), ec);
  const std::string start_yaml = out_yaml + ".start.yaml", log = out_yaml + ".log";
  if (Status s = SaveCalibrationYaml(start, start_yaml); !s) return Error{s.error()};
  std::vector<std::string> args = {Topostation(), "calibrate", "rig"};
  args.insert(args.end(), station_dirs.begin(), station_dirs.end());
  args.insert(args.end(), {"--calibration", start_yaml, "--out", out_yaml, "--json"});
  if (refine_cameras) args.push_back("--refine-cameras");
  const Result<pid_t> spawned = SpawnWithLog(args, log);
  if (!spawned) return Error{spawned.error()};
  const pid_t pid = *spawned;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (should_stop && should_stop()) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return Error{"calibrate rig: cancelled"};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::string last = LastLine(log);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return Error{"calibrate rig failed: " + (last.empty() ? "no output" : last)};
  nlohmann::json report = nlohmann::json::parse(last, nullptr, false);
  if (report.is_discarded()) return Error{"calibrate rig: no report in " + log};
  return report;
}

}  // namespace ts::daemon
