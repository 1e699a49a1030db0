// topostation diff BEFORE AFTER --out DIR: what changed at a site between two epochs (DEM of
// difference, level of detection, areas, volumes, deepest subsidence, subsidence regions).
// BEFORE and AFTER are processed station directories or DEM GeoTIFFs.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "station/commands.h"
#include "station/diff_products.h"
#include "station/option_flags.h"

namespace ts {
namespace {

struct DiffArgs {
  std::string before, after, out, truth;
  ChangeOptions options;
  bool json = false;
};

void Run(const DiffArgs& args) {
  const DiffProducts products =
      WriteDiffProducts(args.before, args.after, args.out, args.options, args.truth);
  const nlohmann::json& j = products.json;
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  const ChangeResult& c = products.change;
  std::printf("DEM of difference (after - before): %d cells compared (%.0f m2)%s\n",
              c.cells_compared, c.area_compared_m2,
              c.after_resampled ? ", AFTER resampled onto BEFORE's grid" : "");
  std::printf(
      "lowering %.0f m2, %.2f +- %.2f m3; raising %.0f m2, %.2f +- %.2f m3; net %+.2f +- %.2f "
      "m3\n",
      c.lowering.area_m2, c.lowering.volume_m3, c.lowering.sigma_m3, c.raising.area_m2,
      c.raising.volume_m3, c.raising.sigma_m3, c.net_volume_m3, c.net_sigma_m3);
  if (c.max_subsidence_m)
    std::printf("max subsidence %.3f +- %.3f m at (%.1f, %.1f)\n", *c.max_subsidence_m,
                c.max_subsidence_sigma_m, c.max_subsidence_xy_m.x(), c.max_subsidence_xy_m.y());
  else
    std::printf("no significant subsidence\n");
  for (const SubsidenceRegion& r : c.regions)
    std::printf("  region %d: %.0f m2, %.2f +- %.2f m3, deepest %.3f +- %.3f m at (%.1f, %.1f)\n",
                r.id, r.lowering.area_m2, r.lowering.volume_m3, r.lowering.sigma_m3, r.max_depth_m,
                r.max_depth_sigma_m, r.deepest_xy_m.x(), r.deepest_xy_m.y());
  if (j.contains("evaluation"))
    for (const nlohmann::json& b : j["evaluation"]["bowls"]) {
      if (!b["found"].get<bool>()) {
        std::printf("true bowl at (%.1f, %.1f): not found\n", b["centre_l"][0].get<double>(),
                    b["centre_l"][1].get<double>());
        continue;
      }
      std::printf(
          "true bowl at (%.1f, %.1f) = region %d: volume %.2f m3 vs %.2f (%+.1f %%), max depth "
          "%.3f vs %.3f m (%+.1f sigma)\n",
          b["centre_l"][0].get<double>(), b["centre_l"][1].get<double>(), b["region"].get<int>(),
          b["volume_m3"].get<double>(), b["true_volume_m3"].get<double>(),
          100.0 * b["volume_error"].get<double>(), b["max_depth_m"].get<double>(),
          b["true_max_depth_m"].get<double>(), b["max_depth_error_in_sigma"].get<double>());
    }
  std::printf("products: %s (dod.tif, dod_std.tif, dod.png, change.json, subsidence.geojson)\n",
              args.out.c_str());
  for (const std::string& w : c.warnings) std::printf("warning: %s\n", w.c_str());
}

}  // namespace

void AddDiffCommand(CLI::App& app) {
  auto args = std::make_shared<DiffArgs>();
  CLI::App* d = app.add_subcommand(
      "diff", "Change between two epochs: DEM of difference, volumes, subsidence (station or DEM)");
  d->add_option("before", args->before, "earlier epoch: processed station or DEM GeoTIFF")
      ->required();
  d->add_option("after", args->after, "later epoch: processed station or DEM GeoTIFF")->required();
  d->add_option("--out", args->out, "directory for the change products")->required();
  AddDeclaredOption(d, "--lod", args->options, "lod_m");
  AddDeclaredOption(d, "--t-critical", args->options, "t_critical");
  AddDeclaredOption(d, "--remove-offset", args->options, "remove_stable_offset");
  AddDeclaredOption(d, "--min-area", args->options, "min_region_area_m2");
  d->add_option("--truth", args->truth,
                "simulator truth of the later epoch: compare the recovered subsidence with it");
  d->add_flag("--json", args->json, "print change.json to stdout");
  d->callback([args] { Run(*args); });
}

}  // namespace ts
