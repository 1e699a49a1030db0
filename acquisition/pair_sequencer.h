#pragma once
// Taking one stereo pair with the two cameras, as every capture does (a station's panorama,
// a board's calibration views): both triggered together, a lost or incomplete frame triggered
// again (a camera whose control channel was lost reopened), and the pair retaken with a
// corrected exposure, both cameras locked together, until it passes the exposure check.
#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "acquisition/capture.h"

namespace ts {

// "pair 07": how logs and errors name a pair.
std::string PairName(int index);

struct PairFrames {
  Frame left, right;
  StagePose readback;
  std::optional<Eigen::Vector2d> inclinometer_deg;  // read with the stage at rest there
};

class PairSequencer {
 public:
  PairSequencer(Camera& left, Camera& right, const CaptureOptions& o,
                const std::function<void(const CaptureEvent&)>& progress, CaptureSummary* summary)
      : left_(left), right_(right), o_(o), progress_(progress), summary_(summary) {}

  double exposure_us = 0.0;
  PairTimeline timeline;  // of the pair being taken

  // Both frames of one trigger, retried (and the cameras reconnected) on a lost frame.
  Result<std::pair<Frame, Frame>> GrabBoth(int index);
  // A pair that passes the exposure check, retaken with a corrected exposure if needed.
  Result<PairFrames> TakePair(int index, int total);
  // Logs the event and hands it to the progress callback.
  void Emit(const CaptureEvent& e);

 private:
  Camera& left_;
  Camera& right_;
  const CaptureOptions& o_;
  const std::function<void(const CaptureEvent&)>& progress_;
  CaptureSummary* summary_;
};

}  // namespace ts
