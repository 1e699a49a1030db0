// topostation survey --rig RIG.yaml --out STATION: capture and process on a real rig, without
// the daemon.
// topostation survey --sim [--scene NAME | --dem FILE] --out STATION [--truth DIR]: the main
// job end to end on the simulated station, as a field team runs it (issue 21): the rig is
// calibrated at a simulated control field (`calibrate stereo` for the cameras and `calibrate
// rig` for the stage, run as the team runs them), then the simulated cameras and stage are served
// on loopback (in a private network namespace it makes itself), the panorama is captured over the
// real drivers (Aravis, libmodbus), processed with the stage self-calibrated on its own seams, and,
// since the truth is known, the DEM is evaluated against it. --true-calibration (for
// benchmarks that isolate matching from calibration) and --nominal-calibration skip the
// session.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "processing/io/calibration_yaml.h"
#include "sim/calibration_field.h"
#include "sim/sim_server.h"
#include "sim/sim_station.h"
#include "sim/truth.h"
#include "station/child_process.h"
#include "station/commands.h"
#include "station/field_session.h"
#include "station/option_flags.h"
#include "station/private_network.h"
#include "station/sim_station_options.h"

namespace ts {
namespace {

struct SurveyArgs {
  bool sim = false;
  std::string rig_file;
  double instrument_height_m = 0.0;  // 0: the rig file's
  sim::SimStationOptions station;
  std::string out;
  std::string truth;
  std::string calibration_file;  // an earlier session's (--sim)
  bool nominal_calibration = false;
  bool true_calibration = false;
  bool no_self_calibration = false;
  bool bump_rig = false;
  CaptureOptions capture = CaptureOptions::ForSimulatedGround();
  bool single_row = false;
  bool json = false;
};

// Runs this program with `args`, its output to `log`; throws with the log's path on failure.
void RunSelf(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> command = {ThisProgram()};
  command.insert(command.end(), args.begin(), args.end());
  const Result<pid_t> pid = SpawnWithLog(command, log);
  int status = 0;
  if (!pid || ::waitpid(*pid, &status, 0) != *pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw CommandError(args[0] + " " + args[1] + " failed: see " + log);
}

// The field team's calibration: a session at a control field of the station's true rig,
// `calibrate stereo` on it with the stage's design values, then `calibrate rig` on the same
// session: the targets fix where each camera stands at each stage pose, so the offsets the
// station's own panorama cannot see (the rig's height over the tilt axis, which lifts the
// whole DEM) come from the field; the angles that drift with transport are self-calibrated at
// the station. Returns the calibration file.
std::string CalibrateAtAField(const sim::SimStation& station, const std::string& dir,
                              const std::string& truth_dir) {
  const std::string session = dir + "/session", cameras = dir + "/cameras.yaml",
                    out = dir + "/calibration.yaml";
  if (Status s = sim::WriteFieldSession(station.rig, station.scene.seed, {}, session,
                                        truth_dir + "/calibration-session");
      !s)
    throw CommandError(s.error());
  const auto commands = FieldCalibrationCommands(SimulatedFieldSession(session), cameras, out);
  RunSelf(commands[0], dir + "/calibrate.log");
  RunSelf(commands[1], dir + "/calibrate-rig.log");
  return out;
}

// A tripod bumped between its calibration and the survey (issue 21's disturbed rig).
constexpr double kBumpTiltZeroDeg = 0.3;
constexpr double kBumpLevellingDeg = 0.1;

struct Surveyed {
  CaptureSummary captured;
  nlohmann::json report;
  double after_last_pair_s = 0.0;
};

// The capture with each pair matched while the stage moves to the next: the products follow
// the last pair by the station-wide steps only.
Surveyed CaptureAndProcess(const RigConfig& rig, const std::string& out,
                           const ProcessOptions& process, const CaptureOptions& capture, bool tty) {
  StationProcessor processor(out, process);
  auto last_pair = std::chrono::steady_clock::now();
  Surveyed s;
  s.captured = CaptureOrThrow(rig, out, false, capture, tty, [&](const CaptureEvent& e) {
    if (e.kind != CaptureEventKind::kPairCaptured) return;
    processor.AddPair(*e.record, *e.left_image, *e.right_image);
    last_pair = std::chrono::steady_clock::now();
  });
  s.report = FinishOrThrow(&processor);
  s.after_last_pair_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_pair).count();
  return s;
}

void RefuseExistingStation(const std::string& out) {
  if (std::filesystem::exists(out + "/station.json"))
    throw CommandError(out +
                       ": already a station (choose a new --out, or `capture "
                       "--resume` and `process` it)");
}

// The survey on a real rig, without the daemon: capture, the stage self-calibrated on the
// station's seams, the products.
void RunRigSurvey(const SurveyArgs& args) {
  if (!args.calibration_file.empty())
    throw CommandError("survey: --calibration is for --sim; a rig's calibration is its rig file's");
  RefuseExistingStation(args.out);
  Result<RigConfig> rig = LoadRigConfig(args.rig_file);
  if (!rig) throw CommandError(rig.error());
  if (args.instrument_height_m > 0.0)
    if (Status s = rig->calibration.stage.SetInstrumentHeight(args.instrument_height_m); !s)
      throw CommandError("survey: --instrument-height-m: " + s.error() + " (" + args.rig_file +
                         ")");
  ProcessOptions process;
  process.self_calibrate_rig = !args.no_self_calibration;
  CaptureOptions capture;
  capture.plan.upper_poses = !args.single_row;
  capture.initial_exposure_us = args.capture.initial_exposure_us;
  const bool tty = ::isatty(STDERR_FILENO) && !args.json;
  const Surveyed s = CaptureAndProcess(*rig, args.out, process, capture, tty);
  if (args.json) {
    std::printf("%s\n", nlohmann::json{{"station", args.out},
                                       {"capture_s", s.captured.seconds},
                                       {"process_s", s.report["wall_s"]},
                                       {"products_after_last_pair_s", s.after_last_pair_s},
                                       {"report", s.report}}
                            .dump()
                            .c_str());
    return;
  }
  std::printf("survey of %s done: capture %.0f s, products %.1f s after the last pair\n",
              args.out.c_str(), s.captured.seconds, s.after_last_pair_s);
  PrintProcessSummary(args.out, s.report);
}

void RunSurvey(const SurveyArgs& args) {
  if (args.sim == !args.rig_file.empty())
    throw CommandError("survey: give --sim (the simulated station) or --rig RIG.yaml, one of them");
  if (!args.sim) return RunRigSurvey(args);
  RefuseExistingStation(args.out);
  EnsurePrivateStationNetwork();  // may re-execute this command in a namespace of its own
  const auto t0 = std::chrono::steady_clock::now();
  const bool tty = ::isatty(STDERR_FILENO) && !args.json;
  const std::string truth_dir = args.truth.empty() ? args.out + "-truth" : args.truth;

  if (args.nominal_calibration + args.true_calibration + !args.calibration_file.empty() > 1)
    throw CommandError(
        "survey: --calibration, --nominal-calibration or --true-calibration, one of them");
  auto built = sim::BuildSimStation(args.station);
  if (!built) throw CommandError(built.error());
  std::shared_ptr<const sim::SimStation> station = *built;
  ProcessOptions process;
  std::string calibration_used;
  RigConfig rig;
  if (!args.nominal_calibration && !args.true_calibration) {
    process.calibration_file =
        args.calibration_file.empty()
            ? CalibrateAtAField(*station, args.out + "-calibration", truth_dir)
            : args.calibration_file;
    const Result<Calibration> calibrated = LoadCalibrationYaml(process.calibration_file);
    if (!calibrated) throw CommandError(calibrated.error());
    rig.calibration = *calibrated;
    process.self_calibrate_rig = !args.no_self_calibration;
    calibration_used =
        std::string(args.calibration_file.empty() ? "estimated: a control-field session"
                                                  : "estimated: an earlier session") +
        " (" + process.calibration_file + ")" +
        (args.no_self_calibration ? ", the stage as calibrated"
                                  : ", the stage self-calibrated on the seams");
  }
  if (args.bump_rig) {  // after the calibration session, before the survey
    auto bumped = std::make_shared<sim::SimStation>(*station);
    sim::BumpTripod(&bumped->rig, kBumpTiltZeroDeg, kBumpLevellingDeg);
    station = bumped;
  }
  if (args.nominal_calibration) {
    rig.calibration = station->rig.nominal;
    calibration_used = "the rig's design values";
  } else if (args.true_calibration) {
    rig.calibration = station->rig.truth;
    process.calibration_file = truth_dir + "/calibration.yaml";
    process.set_up_from_calibration_file = true;  // the truth is this station's own
    calibration_used = "the simulator's true calibration (and the station's true levelling)";
  }
  if (Status s = sim::WriteTruthDirectory(station->scene, station->rig, truth_dir); !s)
    throw CommandError(s.error());
  sim::SimServeOptions serve;
  auto server = sim::SimServer::Start(station, serve);
  if (!server) throw CommandError(server.error());

  rig.name = "simulated-rig";
  rig.file = "(survey --sim)";
  rig.left_camera.id = serve.left_serial;
  rig.right_camera.id = serve.right_serial;
  rig.stage.host = serve.stage_address;
  rig.stage.port = serve.stage_port;
  CaptureOptions capture = args.capture;
  capture.plan.upper_poses = !args.single_row;

  const Surveyed surveyed = CaptureAndProcess(rig, args.out, process, capture, tty);
  const CaptureSummary& captured = surveyed.captured;
  const nlohmann::json& report = surveyed.report;
  const double after_last_pair_s = surveyed.after_last_pair_s;
  server->reset();
  const nlohmann::json evaluation = EvaluateOrThrow(args.out, truth_dir);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (args.json) {
    std::printf("%s\n", nlohmann::json{{"station", args.out},
                                       {"truth", truth_dir},
                                       {"calibration", calibration_used},
                                       {"capture_s", captured.seconds},
                                       {"process_s", report["wall_s"]},
                                       {"products_after_last_pair_s", after_last_pair_s},
                                       {"survey_s", seconds},
                                       {"evaluation", evaluation}}
                            .dump()
                            .c_str());
    return;
  }
  std::printf(
      "survey of scene '%s' done in %.0f s (capture %.0f s; products %.1f s after the last "
      "pair)\n",
      station->scene.name.c_str(), seconds, captured.seconds, after_last_pair_s);
  std::printf(
      "products: %s/products (dem.tif, dem_std.tif, dem.png, points.ply, panorama.png, "
      "terrain_correction.json, report.json); truth: %s\n",
      args.out.c_str(), truth_dir.c_str());
  std::printf("calibration: %s\n", calibration_used.c_str());
  PrintEvaluation(evaluation);  // the warnings went to the log as they came
}

}  // namespace

void AddSurveyCommand(CLI::App& app) {
  auto args = std::make_shared<SurveyArgs>();
  CLI::App* s = app.add_subcommand(
      "survey", "Capture and process a station end to end (--sim: on the simulated station)");
  s->add_flag("--sim", args->sim, "survey the simulated station");
  s->add_option("--rig", args->rig_file, "survey with a real rig (its config, YAML)");
  s->add_option("--instrument-height-m", args->instrument_height_m,
                "the tilt axis's height above the mark, taped now to its trunnion mark (--rig; "
                "default: the rig file's)")
      ->check(CLI::Range(0.05, 10.0));
  AddSimStationOptions(s, &args->station);
  s->add_option("--out", args->out, "station directory to create")->required();
  s->add_option("--truth", args->truth, "truth directory (default: STATION-truth beside it)");
  AddDeclaredOption(s, "--exposure-us", args->capture, "initial_exposure_us");
  s->add_option("--calibration", args->calibration_file,
                "--sim: the rig's calibration from an earlier session of this rig (default: a "
                "control-field session first, written beside --out)");
  s->add_flag("--nominal-calibration", args->nominal_calibration,
              "capture and process with the rig's design values (no calibration session)");
  s->add_flag("--true-calibration", args->true_calibration,
              "capture and process with the simulator's true calibration (no calibration "
              "session, no self-calibration): isolates matching from calibration");
  s->add_flag("--no-self-calibrate-rig", args->no_self_calibration,
              "process with the stage as calibrated (the seams are still checked)");
  s->add_flag("--bump-rig", args->bump_rig,
              "the tripod bumped after the calibration session: tilt zero +0.3 deg, levelling "
              "+0.1 deg");
  s->add_flag("--single-row", args->single_row,
              "no poses higher up where the terrain goes on above a view");
  s->add_flag("--json", args->json, "print the summary as JSON");
  s->callback([args] { RunSurvey(*args); });
}

}  // namespace ts
