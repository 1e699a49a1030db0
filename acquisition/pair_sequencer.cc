#include "acquisition/pair_sequencer.h"

#include <cstdio>

#include "core/log.h"
#include "core/seconds.h"

namespace ts {

using Clock = std::chrono::steady_clock;

std::string PairName(int index) {
  char name[16];
  std::snprintf(name, sizeof(name), "pair %02d", index);
  return name;
}

Result<std::pair<Frame, Frame>> PairSequencer::GrabBoth(int index) {
  std::string last_error;
  int failures[2] = {0, 0};
  int counted = 0, attempt = 0;
  const auto first_trigger = Clock::now();
  for (; counted < o_.frame_attempts; ++attempt) {
    if (attempt > 0) ++summary_->frame_retries;
    // Each camera answers for itself: a trigger the right camera missed says nothing about
    // the left one (whose frame, if any, is waited for and dropped with the pair).
    const auto triggered = Clock::now();
    const Status tl = left_.Trigger();
    const Status tr = right_.Trigger();
    Result<Frame> l = tl ? left_.WaitFrame(o_.frame_timeout) : Result<Frame>(Error{tl.error()});
    Result<Frame> r = tr ? right_.WaitFrame(o_.frame_timeout) : Result<Frame>(Error{tr.error()});
    timeline.trigger_to_frame_s += Seconds(Clock::now() - triggered);
    ++timeline.triggers;
    if (l && r) {
      const uint64_t resent = l->statistics.resent_packets + r->statistics.resent_packets;
      if (resent > 0) Log().info("{}: {} GVSP packets lost and resent", PairName(index), resent);
      summary_->resent_packets += resent;
      return std::pair{std::move(*l), std::move(*r)};
    }
    last_error = !l ? l.error() : r.error();
    Emit({CaptureEventKind::kFrameRetry, index, 0, last_error});
    const bool answering = !left_.ControlLost() && !right_.ControlLost();
    if (!answering || Clock::now() - first_trigger >= o_.pair_budget) ++counted;
    // A camera that lost its control channel, or failed twice, is opened again.
    for (int i = 0; i < 2; ++i) {
      Camera& c = i == 0 ? left_ : right_;
      if (i == 0 ? l.ok() : r.ok()) continue;
      if (!c.ControlLost() && ++failures[i] < 2) continue;
      if (Status s = c.Reconnect(o_.reconnect_budget); !s)
        return Error{c.Describe() + " lost at " + PairName(index) + ": " + last_error +
                     "; reconnecting failed: " + s.error()};
      if (Status s = c.SetExposure(exposure_us, o_.gain_db); !s) return Error{s.error()};
    }
  }
  return Error{"no complete frame pair at " + PairName(index) + " after " +
               std::to_string(attempt) + " triggers: " + last_error};
}

Result<PairFrames> PairSequencer::TakePair(int index, int total) {
  for (int retake = 0;; ++retake) {
    Result<std::pair<Frame, Frame>> frames = GrabBoth(index);
    if (!frames) return Error{frames.error()};
    const auto judged = Clock::now();
    const ExposureVerdict v =
        JudgeExposure(frames->first.image, frames->second.image, exposure_us, o_.exposure);
    timeline.verify_s += Seconds(Clock::now() - judged);
    if (v.ok || retake >= o_.max_retakes)
      return PairFrames{std::move(frames->first), std::move(frames->second), {}, {}};
    ++summary_->retakes;
    Emit({CaptureEventKind::kRetake, index, total,
          v.reason + ": exposure " + std::to_string(exposure_us) + " -> " +
              std::to_string(v.next_exposure_us) + " us"});
    exposure_us = v.next_exposure_us;
    for (Camera* c : {&left_, &right_})
      if (Status s = c->SetExposure(exposure_us, o_.gain_db); !s) return Error{s.error()};
  }
}

void PairSequencer::Emit(const CaptureEvent& e) {
  if (e.kind == CaptureEventKind::kRetake)
    Log().info("{} retaken: {}", PairName(e.pair), e.message);
  if (e.kind == CaptureEventKind::kFrameRetry)
    Log().warn("{} triggered again: {}", PairName(e.pair), e.message);
  if (e.kind == CaptureEventKind::kUpperPose) Log().info("{}: {}", PairName(e.pair), e.message);
  if (progress_) progress_(e);
}

}  // namespace ts
