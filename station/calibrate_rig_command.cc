// `calibrate rig STATION... --calibration CAL.yaml --out CAL.yaml` (issue 21): the stage
// kinematics refined on captured panoramas' own tie points, the cameras and the stereo pair
// held unless --refine-cameras (rig_cameras.h; processing/pipeline/rig_check.h, the same
// check `process` makes). Several stations of the rig join one adjustment: the stage is
// shared, each station's levelling its own. A control field session (`--field-session`: its
// targets measured with the calibration's cameras) joins it as one more set-up, whose surveyed
// targets fix where the cameras stand.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "core/log.h"
#include "processing/calibration/rig_control_field.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/matching/rectification.h"
#include "processing/pipeline/rig_check.h"
#include "processing/pipeline/station_inputs.h"
#include "processing/products/seams_image.h"
#include "station/calibration_report.h"
#include "station/commands.h"
#include "station/field_session.h"
#include "station/option_flags.h"
#include "station/plot_drawing.h"

namespace ts {
namespace {

struct CalibrateRigArgs {
  std::vector<std::string> stations;
  std::string calibration, out;
  std::string field_session, control_field, marks;
  bool json = false;
  RigAdjustmentOptions adjustment;  // refine_cameras from the command line
  // The stations, then the field session: the set-ups of the adjustment, in its order.
  std::vector<std::string> SetUps() const {
    std::vector<std::string> all = stations;
    if (!field_session.empty()) all.push_back(field_session);
    return all;
  }
};

// A station's tie points, with the calibration's stage and the station's levelling and height.
RigAdjustmentInput StationTies(const std::string& station, const std::string& calibration_file,
                               const RigAdjustmentOptions& options) {
  const Result<StationInputs> in = LoadStationInputs(station, calibration_file, "");
  if (!in) throw CommandError(in.error());
  std::vector<StereoPairImages> pairs;
  for (const PairRecord& p : in->manifest.pairs) {
    Result<StereoPairImages> images = LoadPairImages(*in, p);
    if (!images) throw CommandError(images.error());
    pairs.push_back(*std::move(images));
  }
  if (pairs.size() < 2) throw CommandError(station + ": fewer than two pairs: nothing to tie");
  const Calibration& calibration = in->calibration;  // levelled as the station
  const std::vector<MatchedPair> matched =
      MatchPairsIntoL(calibration, Rectify(calibration.rig), pairs, PairMatchOptions::ForStation());
  return StationTiePoints(FindRigTiePoints(calibration, pairs, matched, {}), in->manifest.pairs,
                          options);
}

// The field session's targets, measured with the calibration's cameras, seen from its poses.
RigAdjustmentInput FieldTies(const CalibrateRigArgs& args, const Calibration& calibration) {
  if (args.control_field.empty() || args.marks.empty())
    throw CommandError(
        "--field-session: give --control-field (FIELD.yaml) and --marks (MARKS.yaml, targets "
        "measured by hand)");
  const FieldSessionFiles files = LoadFieldSessionFiles(args.field_session);
  const Result<ControlField> field = LoadControlField(args.control_field);
  if (!field) throw CommandError(field.error());
  const Result<std::vector<ImageMarks>> marks = LoadTargetMarks(args.marks);
  if (!marks) throw CommandError(marks.error());
  FieldViews views;
  views.start = {calibration.rig.left, calibration.rig.right};
  views.images = {LoadFieldImages(files.left, *marks, calibration.rig.left, args.calibration),
                  LoadFieldImages(files.right, *marks, calibration.rig.right, args.calibration)};
  views.second_from_first = calibration.rig.RightFromLeftCamera();
  FieldReport report;
  const Result<std::vector<TargetViews>> measured =
      MeasureFieldTargets(*field, views, FieldCalibrationOptions{}, &report);
  for (const std::string& w : report.warnings) Log().warn("{}", w);
  if (!measured) throw CommandError(args.field_session + ": " + measured.error());
  const Result<RigAdjustmentInput> in = ControlFieldInput(calibration, *measured, files.poses);
  if (!in) throw CommandError(args.field_session + ": " + in.error());
  return *in;
}

RigCheck CheckSetUps(const CalibrateRigArgs& args, const Calibration& calibration) {
  std::vector<RigAdjustmentInput> ties;
  for (const std::string& station : args.stations)
    ties.push_back(StationTies(station, args.calibration, args.adjustment));
  if (!args.field_session.empty()) ties.push_back(FieldTies(args, calibration));
  const Result<RigCheck> check = CheckRig(ties, args.adjustment);
  if (check) return *check;
  const std::vector<std::string> set_ups = args.SetUps();
  throw CommandError((set_ups.size() == 1 ? set_ups[0] : "calibrate rig") + ": " + check.error());
}

void PrintSeams(const char* when, const RigSeams& seams) {
  std::printf("seams %s: median %.2f px (%.1f mm), %.1f %% within 2 of their predicted sigma\n",
              when, seams.median_px, seams.median_mm, 100 * seams.within_2_sigma);
}

void PrintStations(const std::vector<std::string>& stations, const RigCheck& check) {
  const RigAdjustment& r = check.adjustment;
  for (size_t k = 0; k < check.station_after.size(); ++k)
    if (!check.at_control_field[k])
      std::printf("  %s: levelling %+.4f +- %.4f, %+.4f +- %.4f deg; seams after %.1f %%\n",
                  stations[k].c_str(), r.levelling_deg[k].x(), r.levelling_sigma_deg[k].x(),
                  r.levelling_deg[k].y(), r.levelling_sigma_deg[k].y(),
                  100 * check.station_after[k].within_2_sigma);
  for (const RigAdjustment::ControlFit& fit : r.control)
    std::printf(
        "  control field: %d targets, RMS %.3f px, the surveyed points moved %.1f sigma at most "
        "(its set-up's levelling is the field's to turn: held)\n",
        fit.targets, fit.rms_px, fit.largest_move_sigma);
}

// The cameras' parameters that moved by more than a tenth of their sigma, with the sigma a
// posteriori: the rest is in report.json.
void PrintCameras(const RigCheck& check) {
  const RigAdjustment& r = check.adjustment;
  const RigCameraVector before = RigCameraVectorOf(check.start_cameras),
                        after = RigCameraVectorOf(r.cameras.rig),
                        sigma = RigCameraSigmas(r.cameras);
  int quiet = 0;
  for (int i = 0; i < kRigCameraParameterCount; ++i) {
    if (sigma[i] == 0.0 || std::abs(after[i] - before[i]) <= 0.1 * sigma[i]) {
      quiet += sigma[i] > 0.0;
      continue;
    }
    std::printf("  %-32s %+.6g +- %.2g (change %+.2g)\n", RigCameraParameterName(i).c_str(),
                after[i], sigma[i], after[i] - before[i]);
  }
  std::printf("  cameras refined; %d more of their parameters moved by less than 0.1 sigma\n",
              quiet);
}

// The same directory however it is written (a station given twice would count twice).
std::string StationKey(const std::string& station) {
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::canonical(station, ec);
  return ec ? station : canonical.string();
}

void RunCalibrateRig(const CalibrateRigArgs& args) {
  const std::vector<std::string> set_ups = args.SetUps();
  if (set_ups.empty())
    throw CommandError("calibrate rig: give a captured STATION, or a --field-session, or both");
  std::set<std::string> distinct;
  for (const std::string& s : set_ups)
    if (!distinct.insert(StationKey(s)).second) throw CommandError(s + ": given twice");
  const Result<Calibration> given = LoadCalibrationYaml(args.calibration);
  if (!given) throw CommandError(given.error());
  if (args.adjustment.refine_cameras)
    if (Status s = CheckCamerasRefinable(*given); !s)
      throw CommandError(args.calibration + ": " + s.error());
  const RigCheck check = CheckSetUps(args, *given);
  const RigAdjustment& r = check.adjustment;
  const Calibration out = r.Adjusted(*given);
  std::string why;
  if (!out.Check(&why))
    throw CommandError("calibrate rig: the adjusted stage is not valid: " + why);
  if (Status s = SaveCalibrationYaml(out, args.out); !s) throw CommandError(s.error());
  nlohmann::json j = RigCheckJson(check, true);
  if (j.contains("stations"))
    for (size_t k = 0; k < set_ups.size(); ++k) j["stations"][k]["dir"] = set_ups[k];
  else
    j["station"] = set_ups[0];
  if (!args.field_session.empty()) j["control_fields"][0]["dir"] = args.field_session;
  j["out"] = args.out;
  // The report beside the file, as calibrate camera/stereo leave theirs.
  const std::string report = CalibrationReportDir(args.out);
  std::error_code ec;
  std::filesystem::create_directories(report, ec);
  if (ec) throw CommandError(report + ": cannot create (" + ec.message() + ")");
  if (Status s = WriteFileAtomically(report + "/report.json", j.dump(2) + "\n"); !s)
    throw CommandError(s.error());
  if (Status s = WritePng(RenderSeamsImage(check.before, check.after), report + "/seams.png"); !s)
    throw CommandError(s.error());
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  if (check.tie_points > 0) std::printf("%d tie points, ", check.tie_points);
  std::printf("%d observations (%d rejected), RMS %.3f px\n", r.observations, r.rejected, r.rms_px);
  if (!check.before.ties.empty()) {  // a control field alone has no seams
    PrintSeams("before", check.before);
    PrintSeams("after", check.after);
  }
  const StageVector b = StageVectorOf(check.start), a = StageVectorOf(r.stage);
  const bool carried = std::any_of(r.sigma_from_held_cameras.begin(),
                                   r.sigma_from_held_cameras.end(), [](double s) { return s > 0; });
  if (carried) std::printf("  (sigma: of it, the held cameras' calibration's share)\n");
  for (int i = 0; i < kStageParameterCount; ++i) {
    if (r.sigma[i] == 0.0) continue;
    std::printf("  %-22s %+.5f +- %.5f", kStageParameterNames[i], a[i], r.sigma[i]);
    if (carried) std::printf(" (%.5f)", r.sigma_from_held_cameras[i]);
    std::printf(" (change %+.5f)\n", a[i] - b[i]);
  }
  if (r.cameras.refined) PrintCameras(check);
  PrintStations(set_ups, check);
  for (const std::string& w : r.undetermined) std::printf("  %s\n", w.c_str());
  std::printf("written %s, report and seams.png in %s\n", args.out.c_str(),
              CalibrationReportDir(args.out).c_str());
}

}  // namespace

void AddCalibrateRigCommand(CLI::App* calibrate) {
  auto args = std::make_shared<CalibrateRigArgs>();
  CLI::App* rig = calibrate->add_subcommand(
      "rig", "The stage kinematics from a captured panorama's own tie points");
  rig->add_option(
      "STATION", args->stations,
      "captured station directories of the rig (one adjustment, each levelled its own way)");
  rig->add_option("--field-session", args->field_session,
                  "a control field session of the rig (capture --calibration field, or sim "
                  "render --calibration field) joining the adjustment");
  rig->add_option("--control-field", args->control_field,
                  "with --field-session: the surveyed field (FIELD.yaml)");
  rig->add_option("--marks", args->marks,
                  "with --field-session: targets measured by hand (MARKS.yaml), 4 or more in one "
                  "image of each pose");
  rig->add_option("--calibration", args->calibration,
                  "the calibration to refine (its cameras and stereo pair held unless "
                  "--refine-cameras)")
      ->required();
  AddDeclaredOption(rig, "--refine-cameras", args->adjustment, "refine_cameras");
  rig->add_option("--out", args->out, "calibration file (YAML) to write")->required();
  rig->add_flag("--json", args->json, "print one JSON object");
  rig->callback([args] { RunCalibrateRig(*args); });
}

}  // namespace ts
