// topostation sim render|serve: the simulated station (DESIGN.md "Simulator").
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "sim/calibration_field.h"
#include "sim/calibration_views.h"
#include "sim/faults.h"
#include "sim/sim_server.h"
#include "sim/sim_station.h"
#include "sim/truth.h"
#include "station/commands.h"
#include "station/option_flags.h"
#include "station/sim_station_options.h"

namespace ts {
namespace {

struct SceneArgs {
  sim::SimStationOptions station;
  std::string truth_dir;
};

void AddSceneOptions(CLI::App* cmd, SceneArgs* args) {
  AddSimStationOptions(cmd, &args->station);
  cmd->add_option("--truth", args->truth_dir, "ground-truth directory")->required();
}

std::shared_ptr<const sim::SimStation> Build(const SceneArgs& args) {
  auto station = sim::BuildSimStation(args.station);
  if (!station) throw CommandError(station.error());
  return *station;
}

struct RenderArgs {
  SceneArgs scene;
  std::string out;
  sim::StationRenderOptions render;
  bool mono16 = false;
  bool single_row = false;
  std::string calibration;  // a calibration session instead of a station: chessboard | field
  sim::BoardSessionOptions board;
  sim::FieldSessionOptions field;
};

// Calibration views of the station's true rig (the same rig as `sim render` of this seed):
// chessboard or ChArUco placements, or stage poses at a control field.
void RunRenderCalibration(const RenderArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto station = Build(args.scene);
  const uint64_t seed = station->scene.seed;
  const bool board = args.calibration != "field";
  const sim::BoardSessionOptions board_options = sim::BoardSessionOf(args.calibration, args.board);
  const Status s = board ? sim::WriteBoardSession(station->rig, seed, board_options, args.out,
                                                  args.scene.truth_dir)
                         : sim::WriteFieldSession(station->rig, seed, args.field, args.out,
                                                  args.scene.truth_dir);
  if (!s) throw CommandError(s.error());
  const int views = board ? args.board.placements : args.field.poses.pans * args.field.poses.tilts;
  std::printf("calibration session %s (%d %s, seed %llu) rendered in %.1f s; truth in %s\n",
              args.out.c_str(), views, board ? "board placements" : "stage poses at a field",
              static_cast<unsigned long long>(seed),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
              args.scene.truth_dir.c_str());
}

void RunRender(const RenderArgs& args) {
  if (!args.calibration.empty()) return RunRenderCalibration(args);
  const auto t0 = std::chrono::steady_clock::now();
  const auto station = Build(args.scene);
  sim::StationRenderOptions options = args.render;
  options.format = args.mono16 ? PixelFormat::kMono16 : PixelFormat::kMono8;
  options.plan.upper_poses = !args.single_row;
  const bool tty = ::isatty(STDERR_FILENO);
  const Status s = sim::RenderStationDirectory(
      *station, options, args.out, args.scene.truth_dir, [&](int done, int total) {
        if (tty) std::fprintf(stderr, "\rrendering pair %d of %d", done, total);
      });
  if (tty) std::fprintf(stderr, "\n");
  if (!s) throw CommandError(s.error());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("station %s (scene %s, seed %llu) rendered in %.1f s; truth in %s\n",
              args.out.c_str(), station->scene.name.c_str(),
              static_cast<unsigned long long>(station->scene.seed), seconds,
              args.scene.truth_dir.c_str());
}

struct ServeArgs {
  SceneArgs scene;
  sim::SimServeOptions serve;
  std::string faults;
  bool prerender = false;
};

void RunServe(const ServeArgs& args) {
  // Block the stop signals before any thread starts, so only sigwait() below receives them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  sim::SimServeOptions options = args.serve;
  const Result<sim::SimFaults> faults = sim::ParseFaults(args.faults);
  if (!faults) throw CommandError(faults.error());
  options.faults = *faults;
  const auto station = Build(args.scene);
  const Status truth = sim::WriteTruthDirectory(station->scene, station->rig, args.scene.truth_dir);
  if (!truth) throw CommandError(truth.error());
  const Status targets = sim::WriteServedCalibrationTruth(
      station->rig, station->scene.seed, options.calibration, args.scene.truth_dir);
  if (!targets) throw CommandError(targets.error());
  if (args.prerender) options.prerender_targets = sim::DesignPlanTargets(*station);
  auto server = sim::SimServer::Start(station, options);
  if (!server) throw CommandError(server.error());
  nlohmann::json ready = (*server)->Endpoints();
  ready["ready"] = true;
  ready["scene"] = station->scene.name;
  ready["truth"] = args.scene.truth_dir;
  std::printf("%s\n", ready.dump().c_str());
  std::fflush(stdout);
  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  server->reset();  // stops cameras and stage cleanly
}

}  // namespace

void AddSimCommand(CLI::App& app) {
  CLI::App* sim = app.add_subcommand("sim", "Simulated station: scenes, renderer, hardware");
  sim->require_subcommand(1);

  auto render = std::make_shared<RenderArgs>();
  CLI::App* r = sim->add_subcommand(
      "render", "Write a complete station directory from the renderer, and its ground truth");
  AddSceneOptions(r, &render->scene);
  r->add_option("--out", render->out, "station directory to write")->required();
  AddDeclaredOption(r, "--exposure-us", render->render, "exposure_us");
  AddDeclaredOption(r, "--gain-db", render->render, "gain_db");
  AddDeclaredOption(r, "--supersampling", render->render, "render.supersampling");
  r->add_flag("--mono16", render->mono16, "write Mono16 images instead of Mono8");
  r->add_flag("--single-row", render->single_row,
              "no poses higher up where the terrain goes on above a view");
  AddDeclaredOption(r, "--range", render->render, "write_range_images");
  r->add_option("--calibration", render->calibration,
                "render a calibration session of the rig instead of a station: chessboard, "
                "charuco (boards off the frame's edges too), or field (a control field: "
                "field.yaml, marks.yaml, design.yaml); left/ and right/ images, session.json; "
                "the true calibration in --truth")
      ->check(CLI::IsMember({"chessboard", "charuco", "field"}));
  AddDeclaredOption(r, "--placements", render->board, "placements");
  AddDeclaredOption(r, "--board-columns", render->board, "columns");
  AddDeclaredOption(r, "--board-rows", render->board, "rows");
  AddDeclaredOption(r, "--square-m", render->board, "square_m");
  AddDeclaredOption(r, "--board-circle-markers", render->board, "circle_markers");
  AddDeclaredOption(r, "--field-targets", render->field, "targets");
  AddDeclaredOption(r, "--field-pans", render->field, "poses.pans");
  AddDeclaredOption(r, "--field-tilts", render->field, "poses.tilts");
  r->callback([render] { RunRender(*render); });

  auto serve = std::make_shared<ServeArgs>();
  CLI::App* v = sim->add_subcommand(
      "serve", "Serve the simulated cameras (GigE Vision) and stage (Modbus) until SIGTERM");
  AddSceneOptions(v, &serve->scene);
  v->add_option("--faults", serve->faults,
                "key=value,...: gvsp-loss=R, camera-gone=SIDE:after=S:for=S, "
                "stage-stall=AXIS:after=N, stage-alarm=AXIS:after=N, modbus-crc=R, "
                "modbus-drop=R");
  for (const char* name :
       {"left_address", "right_address", "left_serial", "right_serial", "stage_address"}) {
    std::string flag = std::string("--") + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    AddDeclaredOption(v, flag, serve->serve, name);
  }
  AddDeclaredOption(v, "--stage-port", serve->serve, "stage_port");
  AddDeclaredOption(v, "--supersampling", serve->serve, "render.supersampling");
  v->add_option("--calibration", serve->serve.calibration.kind,
                "show the cameras calibration targets instead of the scene: chessboard or "
                "charuco (a board placement per pair), or field (a control field; the field "
                "file and hand marks in --truth)")
      ->check(CLI::IsMember({"chessboard", "charuco", "field"}));
  AddDeclaredOption(v, "--placements", serve->serve, "calibration.board.placements");
  AddDeclaredOption(v, "--board-circle-markers", serve->serve, "calibration.board.circle_markers");
  v->add_flag("--prerender", serve->prerender,
              "render the views of the design plan's poses before serving, so that a capture "
              "with config/sim-rig.yaml is served at once (to time the capture alone)");
  v->callback([serve] { RunServe(*serve); });
}

}  // namespace ts
