#pragma once
// The pieces every processing step shares (Ceres's Solver::Summary, COLMAP's
// CheckIfStopped, PDAL's stage lifecycle): a summary that is filled whether the step succeeds,
// fails or is cancelled; a progress callback; a cancel check asked between steps and pairs.
#include <chrono>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace ts {

// What one step did. Filled on failure too: the steps before it keep their counts.
struct StepSummary {
  std::string name;  // "matching", "ground_filter", ...
  enum class State { kNotRun, kSucceeded, kFailed, kCancelled } state = State::kNotRun;
  double seconds = 0.0;
  std::string message;  // why it failed or was cancelled; empty on success
  nlohmann::json counts = nlohmann::json::object();
  std::vector<std::string> warnings;
};

// Where a running job stands, for a terminal line, the daemon's events or a test.
struct ProcessProgress {
  std::string step;     // the step now running
  int step_number = 0;  // 1-based, of step_count
  int step_count = 0;
  int pairs_done = 0;  // pairs matched so far (the per-pair step)
  int pairs_total = 0;
  double elapsed_s = 0.0;
};

// The caller's hooks. Both are called from the thread that runs the job (for the incremental
// station: also from its matching worker); both may be empty.
struct ProcessControl {
  std::function<void(const ProcessProgress&)> progress;
  std::function<bool()> should_stop;  // true: stop at the next step or pair boundary
  bool StopRequested() const { return should_stop && should_stop(); }
};

// Why a job ended, and what each step did (the station-wide report is built from this).
struct ProcessSummary {
  enum class Termination { kSucceeded, kFailed, kCancelled } termination = Termination::kFailed;
  std::string message;  // the failure or cancellation, naming the step
  std::vector<StepSummary> steps;
  double wall_s = 0.0;
  bool IsUsable() const { return termination == Termination::kSucceeded; }
  const StepSummary* Find(const std::string& name) const;
  std::vector<std::string> Warnings() const;  // of every step, in order
  nlohmann::json TimingsJson() const;         // {step: seconds} of the steps that ran
};

// Runs named steps in order, timing each and filling its summary; a step reports failure by
// returning false after setting summary->message (or by throwing: processing code may throw,
// and the message is caught here, at the job's edge). Stops before a step once the control
// asks to stop.
class StepRunner {
 public:
  StepRunner(const ProcessControl& control, int step_count, ProcessSummary* summary);
  // false when the step (or an earlier one) failed or the job was cancelled.
  bool Run(const std::string& name, const std::function<bool(StepSummary*)>& step);
  // Progress inside the per-pair step; from any thread (the pair tasks).
  void ReportPairs(int done, int total);
  bool ok() const { return ok_; }
  double elapsed_s() const;
  void Finish();  // sets the termination and the wall time

 private:
  void Emit();
  std::mutex progress_mutex_;
  const ProcessControl& control_;
  ProcessSummary* summary_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  ProcessProgress progress_;
  bool ok_ = true;
};

}  // namespace ts
