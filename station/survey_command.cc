// topostation survey --sim [--scene NAME | --dem FILE] --out STATION [--truth DIR]: the main
// job end to end on the simulated station. Serves the simulated cameras and stage on loopback
// (in a private network namespace it makes itself), captures the panorama over the real
// drivers (Aravis, libmodbus), processes it into the products and, since the truth is known,
// evaluates the DEM against it.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "sim/sim_server.h"
#include "sim/sim_station.h"
#include "sim/truth.h"
#include "station/commands.h"
#include "station/option_flags.h"
#include "station/private_network.h"
#include "station/sim_station_options.h"

namespace ts {
namespace {

struct SurveyArgs {
  bool sim = false;
  sim::SimStationOptions station;
  std::string out;
  std::string truth;
  bool nominal_calibration = false;
  CaptureOptions capture = CaptureOptions::ForSimulatedGround();
  bool single_row = false;
  bool json = false;
};

void RunSurvey(const SurveyArgs& args) {
  if (!args.sim)
    throw CommandError(
        "survey: only --sim is available (a real rig: `capture --rig` then "
        "`process`)");
  if (std::filesystem::exists(args.out + "/station.json"))
    throw CommandError(args.out +
                       ": already a station (choose a new --out, or `capture "
                       "--resume` and `process` it)");
  EnsurePrivateStationNetwork();  // may re-execute this command in a namespace of its own
  const auto t0 = std::chrono::steady_clock::now();
  const bool tty = ::isatty(STDERR_FILENO) && !args.json;
  const std::string truth_dir = args.truth.empty() ? args.out + "-truth" : args.truth;

  auto station = sim::BuildSimStation(args.station);
  if (!station) throw CommandError(station.error());
  if (Status s = sim::WriteTruthDirectory((*station)->scene, (*station)->rig, truth_dir); !s)
    throw CommandError(s.error());
  sim::SimServeOptions serve;
  auto server = sim::SimServer::Start(*station, serve);
  if (!server) throw CommandError(server.error());

  RigConfig rig;
  rig.name = "simulated-rig";
  rig.file = "(survey --sim)";
  // The rig knows its calibration: the simulator's true one stands in for a field calibration
  // (below); the capture needs it to judge where the terrain goes on above a view.
  rig.calibration = args.nominal_calibration ? (*station)->rig.nominal : (*station)->rig.truth;
  rig.left_camera.id = serve.left_serial;
  rig.right_camera.id = serve.right_serial;
  rig.stage.host = serve.stage_address;
  rig.stage.port = serve.stage_port;
  CaptureOptions capture = args.capture;
  capture.plan.upper_poses = !args.single_row;

  ProcessOptions process;
  // Until the calibration commands exist, the simulator's true calibration stands in for a
  // field calibration (issue 6); --nominal-calibration shows what the design values give.
  if (!args.nominal_calibration) process.calibration_file = truth_dir + "/calibration.yaml";
  // Each pair is matched while the stage moves to the next: the products follow the last pair
  // by the station-wide steps only.
  StationProcessor processor(args.out, process);
  auto last_pair = std::chrono::steady_clock::now();
  const CaptureSummary captured =
      CaptureOrThrow(rig, args.out, false, capture, tty, [&](const CaptureEvent& e) {
        if (e.kind != CaptureEventKind::kPairCaptured) return;
        processor.AddPair(*e.record, *e.left_image, *e.right_image);
        last_pair = std::chrono::steady_clock::now();
      });
  const nlohmann::json report = FinishOrThrow(&processor);
  const double after_last_pair_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_pair).count();
  server->reset();
  const nlohmann::json evaluation = EvaluateOrThrow(args.out, truth_dir);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (args.json) {
    std::printf("%s\n", nlohmann::json{{"station", args.out},
                                       {"truth", truth_dir},
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
      (*station)->scene.name.c_str(), seconds, captured.seconds, after_last_pair_s);
  std::printf(
      "products: %s/products (dem.tif, dem_std.tif, dem.png, points.ply, panorama.png, "
      "terrain_correction.json, report.json); truth: %s\n",
      args.out.c_str(), truth_dir.c_str());
  PrintEvaluation(evaluation);  // the warnings went to the log as they came
}

}  // namespace

void AddSurveyCommand(CLI::App& app) {
  auto args = std::make_shared<SurveyArgs>();
  CLI::App* s = app.add_subcommand(
      "survey", "Capture and process a station end to end (--sim: on the simulated station)");
  s->add_flag("--sim", args->sim, "survey the simulated station");
  AddSimStationOptions(s, &args->station);
  s->add_option("--out", args->out, "station directory to create")->required();
  s->add_option("--truth", args->truth, "truth directory (default: STATION-truth beside it)");
  AddDeclaredOption(s, "--exposure-us", args->capture, "initial_exposure_us");
  s->add_flag("--nominal-calibration", args->nominal_calibration,
              "capture and process with the rig's design values instead of the simulator's true "
              "calibration");
  s->add_flag("--single-row", args->single_row,
              "no poses higher up where the terrain goes on above a view");
  s->add_flag("--json", args->json, "print the summary as JSON");
  s->callback([args] { RunSurvey(*args); });
}

}  // namespace ts
