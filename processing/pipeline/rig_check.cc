#include "processing/pipeline/rig_check.h"

#include <algorithm>

#include "processing/geometry/inclinometer.h"

namespace ts {

RigAdjustmentInput StationTiePoints(RigAdjustmentInput found, const std::vector<PairRecord>& pairs,
                                    const RigAdjustmentOptions& options) {
  found.stations = found.Stations();
  RigStation& station = found.stations[0];
  station.inclinometer_deg = station.levelling_deg;
  std::vector<InclinometerReading> readings;
  for (const PairRecord& p : pairs)
    if (p.inclinometer_deg) readings.push_back({p.readback.pan_deg, *p.inclinometer_deg});
  if (const std::optional<LevellingFit> fit =
          FitLevelling(readings, found.calibration.stage, options.inclinometer_noise_deg)) {
    station.inclinometer_deg = fit->levelling_deg;
    station.inclinometer_sigma_deg = fit->levelling_sigma_deg;
  }
  return found;
}

Result<RigCheck> CheckRig(const std::vector<RigAdjustmentInput>& stations,
                          const RigAdjustmentOptions& adjustment_options) {
  if (stations.empty()) return Error{"rig check: no station"};
  const RigAdjustmentInput tie = stations.size() == 1 ? stations[0] : JoinStations(stations);
  Result<RigAdjustment> adjusted = AdjustRig(tie, adjustment_options);
  if (!adjusted) return Error{adjusted.error()};
  RigCheck check;
  check.start = tie.calibration.stage;
  check.start_cameras = tie.calibration.rig;
  check.stations = tie.Stations();
  check.at_control_field.assign(check.stations.size(), 0);
  for (const RigControlField& field : tie.control_fields) check.at_control_field[field.station] = 1;
  check.adjustment = std::move(*adjusted);
  check.adjustment.stage.height_above_mark_m = check.start.height_above_mark_m;
  const std::vector<char> control = tie.ControlPoints();
  check.tie_points = static_cast<int>(std::count(control.begin(), control.end(), 0));
  const Calibration after = check.adjustment.Adjusted(tie.calibration);
  check.before = MeasureRigSeams(tie, tie.calibration, check.adjustment);
  check.after = MeasureRigSeams(tie, after, check.adjustment);
  if (stations.size() > 1)
    for (size_t s = 0; s < stations.size(); ++s)
      check.station_after.push_back(
          MeasureRigSeams(tie, after, check.adjustment, static_cast<int>(s)));
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
    parameters[kStageParameterNames[i]] = {
        {"value", after[i]},
        {"sigma", r.sigma[i]},
        {"sigma_from_held_cameras", r.sigma_from_held_cameras[i]},
        {"change", after[i] - before[i]},
        {"held", r.sigma[i] == 0.0}};
  nlohmann::json j = {
      {"used", used},
      {"tie_points", check.tie_points},
      {"observations", r.observations},
      {"rejected", r.rejected},
      {"rms_px", r.rms_px},
      {"image_sigma_px", r.image_sigma_px},
      {"seams", {{"before", SeamsJson(check.before)}, {"after", SeamsJson(check.after)}}},
      {"parameters", parameters},
      {"undetermined", r.undetermined}};
  if (r.cameras.refined) {
    const RigCameraVector before = RigCameraVectorOf(check.start_cameras),
                          after = RigCameraVectorOf(r.cameras.rig),
                          sigma = RigCameraSigmas(r.cameras);
    nlohmann::json cameras = nlohmann::json::object();
    for (int i = 0; i < kRigCameraParameterCount; ++i)
      cameras[RigCameraParameterName(i)] = {{"value", after[i]},
                                            {"sigma", sigma[i]},
                                            {"change", after[i] - before[i]},
                                            {"held", sigma[i] == 0.0}};
    j["cameras"] = cameras;
  }
  if (!r.control.empty()) {
    nlohmann::json fields = nlohmann::json::array();
    for (const RigAdjustment::ControlFit& fit : r.control)
      fields.push_back({{"targets", fit.targets},
                        {"rms_px", fit.rms_px},
                        {"image_sigma_px", fit.image_sigma_px},
                        {"largest_move_sigma", fit.largest_move_sigma}});
    j["control_fields"] = fields;
  }
  if (!check.station_after.empty()) {
    nlohmann::json stations = nlohmann::json::array();
    for (size_t k = 0; k < check.station_after.size(); ++k) {
      const Eigen::Vector2d start = check.stations[k].levelling_deg;
      const Eigen::Vector2d value = r.levelling_deg[k], sigma = r.levelling_sigma_deg[k];
      nlohmann::json station = {
          {"levelling_x_deg",
           {{"value", value.x()}, {"sigma", sigma.x()}, {"change", value.x() - start.x()}}},
          {"levelling_y_deg",
           {{"value", value.y()}, {"sigma", sigma.y()}, {"change", value.y() - start.y()}}}};
      const RigStation& set_up = check.stations[k];
      if (set_up.inclinometer_deg) {
        // Fitted to the readings round the pan (its own sigma), or the one reading at home.
        station["inclinometer"] = {
            {"levelling_deg", {set_up.inclinometer_deg->x(), set_up.inclinometer_deg->y()}},
            {"fitted_round_the_pan", set_up.inclinometer_sigma_deg > 0.0}};
        if (set_up.inclinometer_sigma_deg > 0.0)
          station["inclinometer"]["sigma_deg"] = set_up.inclinometer_sigma_deg;
      }
      if (check.at_control_field[k])
        station["control_field"] = true;  // its levelling held, the field's pose turns it
      else
        station["seams_after"] = SeamsJson(check.station_after[k]);
      stations.push_back(station);
    }
    j["stations"] = stations;
  }
  return j;
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
