// Renderer speed: one 1392 x 1040 view (2 x 2 supersampling, Mono8) on one core, for every
// built-in scene. Target (issue 3): <= 1 s per view.
#include "sim/sim_station.h"
#include "tests/bench/bench_table.h"

int main(int argc, char** argv) {
  using namespace ts;
  bench::Table table("renderer: one 1392x1040 view, 2x2 supersampling, one core");
  std::string only;  // --scene NAME: one scene only (for profiling)
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--scene") only = argv[i + 1];
  for (const std::string& name : sim::BuiltinSceneNames()) {
    if (!only.empty() && name != only) continue;
    sim::SimStationOptions options;
    options.scene = name;
    const auto station = sim::BuildSimStation(options);
    if (!station) {
      std::fprintf(stderr, "%s\n", station.error().c_str());
      return 1;
    }
    const auto plan = MakeCapturePlan((*station)->rig.nominal, {});
    sim::Renderer renderer((*station)->scene, (*station)->mesh);
    sim::RenderStats stats;
    const double seconds = bench::BestSeconds(2, [&] {
      sim::FrameRequest request;
      request.pan_deg = plan[1].pan_deg;
      request.tilt_deg = plan[1].tilt_deg;
      sim::RenderFrame(renderer, **station, request);
      stats = renderer.last_stats();
    });
    table.Add({name + ": view render", seconds, "s", "<= 1.0", seconds <= 1.0});
    table.Add({name + ":   of which visibility", stats.rasterize_s, "s", ""});
    table.Add({name + ":   of which shading", stats.shade_s, "s", ""});
  }
  return table.Finish(argc, argv);
}
