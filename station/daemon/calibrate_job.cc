#include "station/daemon/calibrate_job.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "processing/io/calibration_yaml.h"
#include "station/child_process.h"
#include "station/field_session.h"

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

// Runs `args`, its output to `log`; the JSON report on its last line, or the error with that
// line. Killed when `should_stop` says so (asked every 100 ms).
Result<nlohmann::json> RunWithJsonReport(const std::string& what,
                                         const std::vector<std::string>& args,
                                         const std::string& log,
                                         const std::function<bool()>& should_stop) {
  const Result<pid_t> spawned = SpawnWithLog(args, log);
  if (!spawned) return Error{spawned.error()};
  const pid_t pid = *spawned;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (should_stop && should_stop()) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return Error{what + ": cancelled"};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::string last = LastLine(log);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return Error{what + " failed: " + (last.empty() ? "no output" : last)};
  nlohmann::json report = nlohmann::json::parse(last, nullptr, false);
  if (report.is_discarded()) return Error{what + ": no report in " + log};
  return report;
}

}  // namespace

Result<nlohmann::json> CalibrateRigInChild(const std::vector<std::string>& station_dirs,
                                           const Calibration& start, bool refine_cameras,
                                           const std::string& out_yaml,
                                           const std::function<bool()>& should_stop) {
  std::error_code ec;
  fs::create_directories(fs::path(out_yaml).parent_path(), ec);
  const std::string start_yaml = out_yaml + ".start.yaml";
  if (Status s = SaveCalibrationYaml(start, start_yaml); !s) return Error{s.error()};
  std::vector<std::string> args = {Topostation(), "calibrate", "rig"};
  args.insert(args.end(), station_dirs.begin(), station_dirs.end());
  args.insert(args.end(), {"--calibration", start_yaml, "--out", out_yaml, "--json"});
  if (refine_cameras) args.push_back("--refine-cameras");
  return RunWithJsonReport("calibrate rig", args, out_yaml + ".log", should_stop);
}

Result<nlohmann::json> CalibrateFieldInChild(const std::string& session_dir, int64_t job_id,
                                             const ControlField& field,
                                             const std::vector<ImageMarks>& marks,
                                             const std::string& out_yaml,
                                             const std::function<bool()>& should_stop) {
  std::error_code ec;
  fs::create_directories(fs::path(out_yaml).parent_path(), ec);
  const std::string n = std::to_string(job_id);
  const std::string field_yaml = session_dir + "/field-job-" + n + ".yaml";
  const std::string marks_yaml = session_dir + "/marks-job-" + n + ".yaml";
  if (Status s = SaveControlField(field, field_yaml); !s) return Error{s.error()};
  if (Status s = SaveTargetMarks(marks, marks_yaml); !s) return Error{s.error()};
  // The cameras, then the stage on the same session (the globs are the commands' own).
  const std::string cameras_yaml = out_yaml + ".cameras.yaml";
  const FieldSessionInputs session = {
      session_dir, session_dir + "/raw/*_left.png", session_dir + "/raw/*_right.png", field_yaml,
      marks_yaml,  session_dir + "/design.yaml"};
  std::vector<std::vector<std::string>> commands =
      FieldCalibrationCommands(session, cameras_yaml, out_yaml);
  for (std::vector<std::string>& c : commands) {
    c.insert(c.begin(), Topostation());
    c.push_back("--json");
  }
  Result<nlohmann::json> report =
      RunWithJsonReport("calibrate stereo", commands[0], cameras_yaml + ".log", should_stop);
  if (!report) return report;
  Result<nlohmann::json> stage =
      RunWithJsonReport("calibrate rig", commands[1], out_yaml + ".log", should_stop);
  if (!stage) return stage;
  (*report)["stage"] = std::move(*stage);
  return report;
}

}  // namespace ts::daemon
