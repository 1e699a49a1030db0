#pragma once
// The capture sequencer: moves the stage through the capture plan and stores one verified
// stereo pair per pose in a station directory (DESIGN.md "Station directory").
//
//   for each pose not yet captured:
//     wait in position (read back) -> trigger both cameras -> grab both -> verify (status,
//     size, exposure; retake with a corrected exposure, both cameras locked together) ->
//     if the terrain goes on above the view, append the pose above it to the plan and take it
//     next (terrain_above_view.h) -> start the move to the next pose -> write both images
//     atomically -> commit the pair (and the grown plan) to the manifest
//
// The stage moves while the pair just taken is written. The manifest is written before the
// first pair and after every pair, so a capture stopped at any moment (power, kill -9, a lost
// camera) leaves a station directory that validates, and `resume` captures exactly the
// missing pairs. Errors name the device and the pair.
#include <atomic>
#include <chrono>
#include <functional>
#include <string>

#include "acquisition/exposure_control.h"
#include "acquisition/rig_config.h"
#include "core/exposure.h"
#include "devices/camera.h"
#include "devices/stage.h"
#include "processing/geometry/capture_plan.h"
#include "processing/io/station_manifest.h"

namespace ts {

struct CaptureOptions {
  CapturePlanOptions plan;
  // Poses planned elsewhere (a control field's grid, MakeFieldPoseGrid): taken as they are,
  // none added above them. Empty: the panorama of `plan`.
  std::vector<StagePose> given_plan;
  ExposureOptions exposure;
  double initial_exposure_us = kDefaultExposureUs;
  double gain_db = 0.0;
  PixelFormat format = PixelFormat::kMono8;
  double position_tolerance_deg = 0.05;
  std::chrono::milliseconds home_timeout{30000};
  std::chrono::milliseconds move_timeout{20000};
  std::chrono::milliseconds frame_timeout{3000};
  int frame_attempts = 3;  // triggers with a camera not answering before it counts as lost
  // While both cameras still answer their control channel, a late or torn frame is a busy
  // laptop or network, not a lost camera: the pair is triggered again for this long.
  std::chrono::milliseconds pair_budget{60000};
  int max_retakes = 4;  // exposure corrections per pair
  std::chrono::milliseconds reconnect_budget{6000};
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("initial_exposure_us", self.initial_exposure_us,
      {"exposure of the first pair", "us", 1, 10000000});
    v("gain_db", self.gain_db, {"camera gain", "dB", 0, 48});
    v("format", self.format, {"pixel format (0 Mono8, 1 Mono16)"});
    v("position_tolerance_deg", self.position_tolerance_deg,
      {"a pose is reached within this", "deg", 0.001, 5});
    v("home_timeout", self.home_timeout, {"homing may take this long", "ms", 1000, 600000});
    v("move_timeout", self.move_timeout, {"a move may take this long", "ms", 1000, 600000});
    v("frame_timeout", self.frame_timeout, {"a frame may take this long", "ms", 100, 120000});
    v("frame_attempts", self.frame_attempts,
      {"triggers with a camera not answering before it counts as lost", "", 1, 100});
    v("pair_budget", self.pair_budget,
      {"a pair whose cameras still answer is triggered again for this long", "ms", 0, 600000});
    v("max_retakes", self.max_retakes, {"exposure corrections per pair", "", 0, 100});
    v("reconnect_budget", self.reconnect_budget, {"time to reopen a lost camera", "ms", 0, 600000});
    v.Group("plan", self.plan);
    v.Group("exposure", self.exposure);
  }
  bool Check(std::string* why) const;
  // The simulated ground sits near 60 % of full scale under every scene's sun, brighter than
  // kDefaultExposureUs assumes of real daylight: start the simulated survey shorter (the
  // exposure control keeps a pair between 12 and 75 % either way).
  static CaptureOptions ForSimulatedGround() {
    CaptureOptions o;
    o.initial_exposure_us = 7000.0;
    return o;
  }
};

enum class CaptureEventKind {
  kStarted,
  kMoving,
  kPairCaptured,
  kRetake,
  kFrameRetry,
  kUpperPose,
  kFinished
};

struct CaptureEvent {
  CaptureEventKind kind = CaptureEventKind::kStarted;
  int pair = -1;  // plan index
  int total = 0;
  std::string message;
  int captured = 0;  // pairs the station holds (kMoving, kPairCaptured)
  // kPairCaptured: the record just committed and its images (valid during the call only; the
  // images may be shared, never modified), for an incremental station to match at once.
  const PairRecord* record = nullptr;
  const cv::Mat* left_image = nullptr;
  const cv::Mat* right_image = nullptr;
};

struct CaptureSummary {
  int total_pairs = 0;
  int captured_now = 0;
  int already_present = 0;
  int retakes = 0;              // exposure corrections
  int frame_retries = 0;        // re-triggers after a lost or incomplete frame
  uint64_t resent_packets = 0;  // GVSP packets lost and recovered by resend, both cameras
  double seconds = 0.0;
  double exposure_us = 0.0;  // of the last pair
  nlohmann::json timeline;   // of the pairs captured now (CaptureTimelineJson)
};

Result<CaptureSummary> CaptureStation(
    Stage& stage, Camera& left, Camera& right, const RigConfig& rig, const std::string& station_dir,
    bool resume, const CaptureOptions& options,
    const std::function<void(const CaptureEvent&)>& progress = {});

}  // namespace ts
