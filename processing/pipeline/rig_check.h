#pragma once
// The rig checked on every station's own panorama (issue 21): tie points between the pairs'
// overlaps (rig_tie_points.h), the stage kinematics adjusted on them (rig_adjustment.h) and the
// seams measured before and after (rig_seams.h). `process` always checks, and warns when the
// seams of the calibration it was given do not close (a bumped tripod, a stage that moved on
// its mount); with --self-calibrate-rig it goes on with the adjusted stage.
//
// The levelling and the height above the mark belong to the station, not to the rig: the
// start is levelled as the station (station_inputs.h), and the inclinometer's reading at
// capture is also the levelling's observation.
#include <nlohmann/json.hpp>
#include <vector>

#include "core/result.h"
#include "processing/calibration/rig_adjustment.h"
#include "processing/calibration/rig_seams.h"
#include "processing/calibration/rig_tie_points.h"
#include "processing/io/station_manifest.h"
#include "processing/matching/station_matching.h"

namespace ts {

struct RigCheck {
  StageKinematics start;  // the calibration's stage with the (first) station's levelling and height
  StereoRig start_cameras;
  std::vector<RigStation> stations;  // each station's levelling at the start, and its reading
  RigAdjustment adjustment;
  RigSeams before, after;  // of every station
  // Several stations: each one's seams after the adjustment, in their order.
  std::vector<RigSeams> station_after;
  std::vector<char> at_control_field;  // per station: a control field's set-up (no seams)
  int tie_points = 0;                  // of the panoramas (a control field's targets are not)
  // The seams of the start close: at least this share of the tie points within 2 of their
  // predicted sigma (a 2D normal error gives 98 %; real tie points, with their heavier tail,
  // 94-96 % on the true calibration).
  static constexpr double kClosedShare = 0.9;
  bool SeamsClose() const { return before.within_2_sigma >= kClosedShare; }
};

// A station's tie points (rig_tie_points.h, found with the calibration levelled as the station:
// station_inputs.h) and its inclinometer: the levelling fitted to the readings at the pairs'
// pans when they go round the circle (inclinometer.h: the index error cancels), else the one
// reading at home the station's levelling holds, with the options' sigma for each.
RigAdjustmentInput StationTiePoints(RigAdjustmentInput found, const std::vector<PairRecord>& pairs,
                                    const RigAdjustmentOptions& options);

// One or more stations of one rig (StationTiePoints of each) in one adjustment: the stage
// shared, each station's levelling its own; the seams before and after.
Result<RigCheck> CheckRig(const std::vector<RigAdjustmentInput>& stations,
                          const RigAdjustmentOptions& adjustment_options);

// What report.json records: each parameter with its sigma and change, what was held, the
// seams before and after, and whether the adjusted stage was used; the cameras' parameters
// the same way when they were refined.
nlohmann::json RigCheckJson(const RigCheck& check, bool used);

// A matched pair's points (and covariances), taken into L with `from`'s stage, moved to
// where `to`'s stage puts them.
void MovePairPoints(const Calibration& from, const Calibration& to, MatchedPair* pair);

}  // namespace ts
