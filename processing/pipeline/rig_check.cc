#include "processing/pipeline/rig_check.h"

namespace ts {

Calibration StationStart(const Calibration& calibration, const StationManifest& manifest) {
  Calibration start = calibration;
  const StageKinematics& station = manifest.calibration.stage;
  start.stage.levelling_x_deg = station.levelling_x_deg;
  start.stage.levelling_y_deg = station.levelling_y_deg;
  start.stage.height_above_mark_m = station.height_above_mark_m;
  return start;
}

Result<RigCheck> CheckRig(const Calibration& start, const std::vector<StereoPairImages>& pairs,
                          const std::vector<MatchedPair>& matched,
                          const RigTiePointOptions& tie_options,
                          const RigAdjustmentOptions& adjustment_options) {
  RigAdjustmentInput tie = FindRigTiePoints(start, pairs, matched, tie_options);
  tie.inclinometer_deg = Eigen::Vector2d(start.stage.levelling_x_deg, start.stage.levelling_y_deg);
  Result<RigAdjustment> adjusted = AdjustRig(tie, adjustment_options);
  if (!adjusted) return Error{adjusted.error()};
  RigCheck check;
  check.start = start.stage;
  check.adjustment = std::move(*adjusted);
  check.adjustment.stage.height_above_mark_m = start.stage.height_above_mark_m;
  check.tie_points = static_cast<int>(tie.points.size());
  check.before = MeasureRigSeams(tie, start.stage, check.adjustment);
  check.after = MeasureRigSeams(tie, check.adjustment.stage, check.adjustment);
  return check;
}

namespace {
nlohmann::json SeamsJson(const RigSeams& s) {
  return {{"ties", s.ties.size()},
          {"median_px", s.median_px},
          {"median_mm", s.median_mm},
          {"within_2_sigma", s.within_2_sigma}};
}
}  // namespace

nlohmann::json RigCheckJson(const RigCheck& check, bool used) {
  const RigAdjustment& r = check.adjustment;
  const StageVector before = StageVectorOf(check.start), after = StageVectorOf(r.stage);
  nlohmann::json parameters = nlohmann::json::object();
  for (int i = 0; i < kStageParameterCount; ++i)
    parameters[kStageParameterNames[i]] = {{"value", after[i]},
                                           {"sigma", r.sigma[i]},
                                           {"change", after[i] - before[i]},
                                           {"held", r.sigma[i] == 0.0}};
  return {{"used", used},
          {"tie_points", check.tie_points},
          {"observations", r.observations},
          {"rejected", r.rejected},
          {"rms_px", r.rms_px},
          {"image_sigma_px", r.image_sigma_px},
          {"seams", {{"before", SeamsJson(check.before)}, {"after", SeamsJson(check.after)}}},
          {"parameters", parameters},
          {"undetermined", r.undetermined}};
}

void MovePairPoints(const Calibration& from, const Calibration& to, MatchedPair* pair) {
  const Eigen::Isometry3d move = to.stage.LFromS(pair->pan_deg, pair->tilt_deg) *
                                 from.stage.LFromS(pair->pan_deg, pair->tilt_deg).inverse();
  const Eigen::Matrix3f rotation = move.linear().cast<float>();
  for (CloudPoint& p : pair->cloud) {
    p.position_m = move * p.position_m;
    p.covariance_m2 = rotation * p.covariance_m2 * rotation.transpose();
  }
}

}  // namespace ts
