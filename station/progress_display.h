#pragma once
// The progress line of long commands (capture, process, survey): one line on stderr that
// rewrites itself, only on a terminal and never with --json, with the elapsed time and an
// estimate of what is left. Lines that must stay (a retake, a warning) go above it.
#include <chrono>
#include <string>

namespace ts {

class ProgressDisplay {
 public:
  explicit ProgressDisplay(bool enabled) : enabled_(enabled) {}
  ~ProgressDisplay() { Clear(); }
  bool enabled() const { return enabled_; }
  // "capture: pair 5 of 12, 14 s, ~20 s left": the estimate from the pace so far.
  void Count(const std::string& what, int done, int total);
  // "process: kriging (step 7 of 11), 2.1 s"
  void Step(const std::string& what, const std::string& step, int number, int count);
  void Line(const std::string& text);  // stays, above the progress line
  void Clear();

 private:
  void Show(const std::string& text);
  double Elapsed() const;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace ts
