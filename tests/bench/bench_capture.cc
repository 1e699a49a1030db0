// Capture speed: a 12-pair panorama over the real drivers (Aravis, libmodbus) against the
// simulated station at its default stage dynamics, twice in one run (this VM drifts, so A/B):
//   - rendering on demand: each view is rendered while the stage moves to it (as `sim serve`);
//     target (issue 4) <= 30 s, the paper ~60 s;
//   - pre-rendered (`sim serve --prerender`): every view rendered before the capture starts,
//     so the capture's own overhead shows; target (issue 19) <= 15 s, of which the stage's
//     moves and settling take about 12.5 s.
// The capture timeline (capture.h) says where the time went. The simulated hardware runs in
// this process, as in the system tests; run inside scripts/netns-run (scripts/bench does).
#include <filesystem>

#include "acquisition/capture.h"
#include "devices/aravis_camera.h"
#include "devices/modbus_stage.h"
#include "sim/sim_server.h"
#include "tests/bench/bench_table.h"

namespace {

using namespace ts;

struct Run {
  CaptureSummary summary;
  int frames = 0, waited_for_render = 0;
};

Result<Run> CaptureOnce(const std::shared_ptr<const sim::SimStation>& station, const RigConfig& rig,
                        bool prerender, int port) {
  CaptureOptions options;
  options.plan.upper_poses = false;  // the 12 poses of the row, always
  options.initial_exposure_us = 4000;
  sim::SimServeOptions serve;
  serve.stage_port = port;
  if (prerender) serve.prerender_targets = MakeCapturePlan(rig.calibration, options.plan);
  auto server = sim::SimServer::Start(station, serve);
  if (!server) return Error{server.error()};
  RigConfig local = rig;
  local.stage.port = port;
  auto stage = OpenModbusStage(local.stage);
  auto left = OpenAravisCamera(local.left_camera);
  auto right = OpenAravisCamera(local.right_camera);
  if (!stage || !left || !right) return Error{"devices did not open"};
  const std::string dir =
      (std::filesystem::temp_directory_path() / "topostation-bench-capture").string();
  std::filesystem::remove_all(dir);
  const Result<CaptureSummary> s =
      CaptureStation(**stage, **left, **right, local, dir, false, options);
  std::filesystem::remove_all(dir);
  if (!s) return Error{s.error()};
  Run run{*s};
  for (Side side : {Side::kLeft, Side::kRight}) {
    const auto c = (*server)->camera(side).counters();
    run.frames += c.frames;
    run.waited_for_render += c.waited_for_render;
  }
  return run;
}

void AddRows(bench::Table* table, const std::string& mode, const Run& run, double target_s,
             const std::string& target) {
  const CaptureSummary& s = run.summary;
  table->Add({mode + ": 12 pairs, wall time", s.seconds, "s", target, s.seconds <= target_s});
  const nlohmann::json& total = s.timeline["total_s"];
  const nlohmann::json& median = s.timeline["median_s"];
  table->Add({mode + ":   waiting for the stage", total.value("stage_wait_s", 0.0), "s", ""});
  const std::pair<const char*, const char*> medians[] = {{"stage moving", "move_s"},
                                                         {"stage settling", "settle_s"},
                                                         {"trigger to frame", "trigger_to_frame_s"},
                                                         {"verify", "verify_s"},
                                                         {"write (stage moving)", "write_s"}};
  for (const auto& [label, field] : medians)
    table->Add({mode + ":   " + label + ", median", median.value(field, 0.0), "s", ""});
  table->Add(
      {mode + ":   frames before their view", static_cast<double>(run.waited_for_render), "", ""});
  table->Add({mode + ":   retakes and re-triggers",
              static_cast<double>(s.retakes + s.frame_retries), "", ""});
}

}  // namespace

int main(int argc, char** argv) {
  const auto station = sim::BuildSimStation({});
  if (!station) return std::fprintf(stderr, "%s\n", station.error().c_str()), 1;
  const Result<RigConfig> rig = LoadRigConfig(TS_SOURCE_DIR "/config/sim-rig.yaml");
  if (!rig) return std::fprintf(stderr, "%s\n", rig.error().c_str()), 1;
  const Result<Run> on_demand = CaptureOnce(*station, *rig, false, 15190);
  if (!on_demand) return std::fprintf(stderr, "on demand: %s\n", on_demand.error().c_str()), 1;
  const Result<Run> prerendered = CaptureOnce(*station, *rig, true, 15191);
  if (!prerendered)
    return std::fprintf(stderr, "prerendered: %s\n", prerendered.error().c_str()), 1;
  bench::Table table("capture: 12 stereo pairs against sim serve (real drivers)");
  AddRows(&table, "on demand", *on_demand, 30.0, "<= 30");
  AddRows(&table, "pre-rendered", *prerendered, 15.0, "<= 15");
  return table.Finish(argc, argv);
}
