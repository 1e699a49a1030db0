#include "processing/pipeline/step.h"

#include <exception>

#include "core/log.h"

namespace ts {

const StepSummary* ProcessSummary::Find(const std::string& name) const {
  for (const StepSummary& s : steps)
    if (s.name == name) return &s;
  return nullptr;
}

std::vector<std::string> ProcessSummary::Warnings() const {
  std::vector<std::string> all;
  for (const StepSummary& s : steps) all.insert(all.end(), s.warnings.begin(), s.warnings.end());
  return all;
}

nlohmann::json ProcessSummary::TimingsJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const StepSummary& s : steps)
    if (s.state != StepSummary::State::kNotRun) j[s.name] = s.seconds;
  return j;
}

StepRunner::StepRunner(const ProcessControl& control, int step_count, ProcessSummary* summary)
    : control_(control), summary_(summary) {
  progress_.step_count = step_count;
}

double StepRunner::elapsed_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void StepRunner::Emit() {
  if (!control_.progress) return;
  std::lock_guard lock(progress_mutex_);
  progress_.elapsed_s = elapsed_s();
  control_.progress(progress_);
}

void StepRunner::ReportPairs(int done, int total) {
  {
    std::lock_guard lock(progress_mutex_);
    progress_.pairs_done = done;
    progress_.pairs_total = total;
  }
  Emit();
}

bool StepRunner::Run(const std::string& name, const std::function<bool(StepSummary*)>& step) {
  if (!ok_) return false;
  summary_->steps.push_back({});
  StepSummary* s = &summary_->steps.back();
  s->name = name;
  if (control_.StopRequested()) {
    s->state = StepSummary::State::kCancelled;
    s->message = "cancelled before " + name;
    summary_->termination = ProcessSummary::Termination::kCancelled;
    summary_->message = s->message;
    ok_ = false;
    return false;
  }
  {
    std::lock_guard lock(progress_mutex_);
    ++progress_.step_number;
    progress_.step = name;
  }
  Emit();
  const auto t0 = std::chrono::steady_clock::now();
  bool succeeded = false;
  try {
    succeeded = step(s);
  } catch (const std::exception& e) {
    s->message = e.what();
  }
  s->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const std::string& warning : s->warnings) Log().warn("{}", warning);
  if (succeeded) {
    s->state = StepSummary::State::kSucceeded;
    Log().debug("{}: {:.3f} s {}", name, s->seconds, s->counts.dump());
    return true;
  }
  const bool cancelled = control_.StopRequested();
  s->state = cancelled ? StepSummary::State::kCancelled : StepSummary::State::kFailed;
  if (cancelled) s->message = "cancelled during " + name;
  if (s->message.empty()) s->message = name + " failed";
  summary_->termination =
      cancelled ? ProcessSummary::Termination::kCancelled : ProcessSummary::Termination::kFailed;
  summary_->message = s->message;
  ok_ = false;
  return false;
}

void StepRunner::Finish() {
  if (ok_) summary_->termination = ProcessSummary::Termination::kSucceeded;
  summary_->wall_s = elapsed_s();
}

}  // namespace ts
