// `calibrate rig STATION --calibration CAL.yaml --out CAL.yaml` (issue 21): the stage
// kinematics refined on a captured panorama's own tie points, the cameras and the stereo pair
// held (processing/calibration/rig_adjustment.h).
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "processing/calibration/rig_seams.h"
#include "processing/calibration/rig_tie_points.h"
#include "processing/io/calibration_yaml.h"
#include "processing/matching/rectification.h"
#include "processing/pipeline/station_inputs.h"
#include "station/commands.h"

namespace ts {
namespace {

struct CalibrateRigArgs {
  std::vector<std::string> stations;
  std::string calibration, out;
  bool json = false;
};

// The station's pairs and the calibration to refine, its levelling the station's own
// inclinometer reading (capture records it in the manifest).
RigAdjustmentInput TiePointsOf(const std::string& station, const std::string& calibration_file) {
  const Result<StationInputs> in = LoadStationInputs(station, calibration_file, "");
  if (!in) throw CommandError(in.error());
  Calibration calibration = in->calibration;
  const StageKinematics& read = in->manifest.calibration.stage;
  calibration.stage.levelling_x_deg = read.levelling_x_deg;
  calibration.stage.levelling_y_deg = read.levelling_y_deg;
  calibration.stage.height_above_mark_m = read.height_above_mark_m;
  std::vector<StereoPairImages> pairs;
  for (const PairRecord& p : in->manifest.pairs) {
    Result<StereoPairImages> images = LoadPairImages(*in, p);
    if (!images) throw CommandError(images.error());
    pairs.push_back(*std::move(images));
  }
  if (pairs.size() < 2) throw CommandError(station + ": fewer than two pairs: nothing to tie");
  const std::vector<MatchedPair> matched =
      MatchPairsIntoL(calibration, Rectify(calibration.rig), pairs, PairMatchOptions::ForStation());
  RigAdjustmentInput tie = FindRigTiePoints(calibration, pairs, matched, {});
  tie.inclinometer_deg = Eigen::Vector2d(read.levelling_x_deg, read.levelling_y_deg);
  return tie;
}

nlohmann::json ParametersJson(const StageKinematics& before, const RigAdjustment& r) {
  const StageVector b = StageVectorOf(before), a = StageVectorOf(r.stage);
  nlohmann::json j = nlohmann::json::object();
  for (int i = 0; i < kStageParameterCount; ++i)
    j[kStageParameterNames[i]] = {
        {"value", a[i]}, {"sigma", r.sigma[i]}, {"change", a[i] - b[i]}, {"held", r.sigma[i] == 0}};
  return j;
}

nlohmann::json SeamsJson(const RigSeams& s) {
  return {{"ties", s.ties.size()},
          {"median_px", s.median_px},
          {"median_mm", s.median_mm},
          {"within_2_sigma", s.within_2_sigma}};
}

void RunCalibrateRig(const CalibrateRigArgs& args) {
  if (args.stations.size() != 1)
    throw CommandError("calibrate rig: one station at a time for now (given " +
                       std::to_string(args.stations.size()) + ")");
  const RigAdjustmentInput tie = TiePointsOf(args.stations[0], args.calibration);
  const Result<RigAdjustment> r = AdjustRig(tie, {});
  if (!r) throw CommandError(args.stations[0] + ": " + r.error());
  Calibration out = tie.calibration;
  out.stage = r->stage;
  out.stage.height_above_mark_m = tie.calibration.stage.height_above_mark_m;
  std::string why;
  if (!out.Check(&why))
    throw CommandError("calibrate rig: the adjusted stage is not valid: " + why);
  if (Status s = SaveCalibrationYaml(out, args.out); !s) throw CommandError(s.error());
  const RigSeams before = MeasureRigSeams(tie, tie.calibration.stage, *r);
  const RigSeams after = MeasureRigSeams(tie, r->stage, *r);
  const nlohmann::json j = {{"station", args.stations[0]},
                            {"tie_points", tie.points.size()},
                            {"observations", r->observations},
                            {"rejected", r->rejected},
                            {"rms_px", r->rms_px},
                            {"image_sigma_px", r->image_sigma_px},
                            {"seams", {{"before", SeamsJson(before)}, {"after", SeamsJson(after)}}},
                            {"parameters", ParametersJson(tie.calibration.stage, *r)},
                            {"undetermined", r->undetermined},
                            {"out", args.out}};
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  std::printf("%zu tie points, %d observations (%d rejected), RMS %.3f px\n", tie.points.size(),
              r->observations, r->rejected, r->rms_px);
  for (const auto& [when, seams] : {std::pair{"before", &before}, std::pair{"after", &after}})
    std::printf("seams %s: median %.2f px (%.1f mm), %.1f %% within 2 of their predicted sigma\n",
                when, seams->median_px, seams->median_mm, 100 * seams->within_2_sigma);
  const StageVector b = StageVectorOf(tie.calibration.stage), a = StageVectorOf(r->stage);
  for (int i = 0; i < kStageParameterCount; ++i)
    if (r->sigma[i] > 0.0)
      std::printf("  %-22s %+.5f +- %.5f (change %+.5f)\n", kStageParameterNames[i], a[i],
                  r->sigma[i], a[i] - b[i]);
  for (const std::string& w : r->undetermined) std::printf("  %s\n", w.c_str());
  std::printf("written %s\n", args.out.c_str());
}

}  // namespace

void AddCalibrateRigCommand(CLI::App* calibrate) {
  auto args = std::make_shared<CalibrateRigArgs>();
  CLI::App* rig = calibrate->add_subcommand(
      "rig", "The stage kinematics from a captured panorama's own tie points");
  rig->add_option("STATION", args->stations, "a captured station directory")->required();
  rig->add_option("--calibration", args->calibration,
                  "the calibration to refine (cameras and stereo pair held)")
      ->required();
  rig->add_option("--out", args->out, "calibration file (YAML) to write")->required();
  rig->add_flag("--json", args->json, "print one JSON object");
  rig->callback([args] { RunCalibrateRig(*args); });
}

}  // namespace ts
