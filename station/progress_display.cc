#include "station/progress_display.h"

#include <cstdio>

namespace ts {
namespace {

std::string Seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, s < 10 ? "%.1f s" : "%.0f s", s);
  return text;
}

}  // namespace

double ProgressDisplay::Elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressDisplay::Show(const std::string& text) {
  if (!enabled_) return;
  std::fprintf(stderr, "\r\033[K%s", text.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void ProgressDisplay::Count(const std::string& what, int done, int total) {
  const double elapsed = Elapsed();
  std::string text =
      what + " " + std::to_string(done) + " of " + std::to_string(total) + ", " + Seconds(elapsed);
  if (done > 0 && done < total) text += ", ~" + Seconds(elapsed / done * (total - done)) + " left";
  Show(text);
}

void ProgressDisplay::Step(const std::string& what, const std::string& step, int number,
                           int count) {
  Show(what + ": " + step + " (step " + std::to_string(number) + " of " + std::to_string(count) +
       "), " + Seconds(Elapsed()));
}

void ProgressDisplay::Line(const std::string& text) {
  if (!enabled_) return;
  Clear();
  std::fprintf(stderr, "%s\n", text.c_str());
}

void ProgressDisplay::Clear() {
  if (!enabled_ || !shown_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  shown_ = false;
}

}  // namespace ts
