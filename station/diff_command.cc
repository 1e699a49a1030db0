// topostation diff BEFORE AFTER --out DIR: what changed at a site between two epochs (DEM of
// difference, level of detection, areas, volumes, deepest subsidence, subsidence regions).
// BEFORE and AFTER are processed station directories or DEM GeoTIFFs.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "processing/change/change_json.h"
#include "processing/change/dem_of_difference.h"
#include "processing/change/subsidence_regions.h"
#include "processing/io/atomic_file.h"
#include "processing/io/image_file.h"
#include "processing/products/dod_image.h"
#include "station/commands.h"
#include "station/dem_input.h"
#include "station/option_flags.h"

namespace ts {
namespace {

struct DiffArgs {
  std::string before, after, out, truth;
  ChangeOptions options;
  bool json = false;
};

// The recovered change against the simulator's truth of the later epoch (truth.json's
// subsidence bowls): each bowl against the subsidence region whose centroid lies nearest its
// centre (within its radius), by volume and deepest point.
nlohmann::json EvaluateAgainstTruth(const ChangeResult& change, const std::string& truth_dir) {
  const std::string file = truth_dir + "/truth.json";
  Result<std::string> text = ReadWholeFile(file);
  if (!text) throw CommandError(text.error());
  const nlohmann::json truth = nlohmann::json::parse(*text, nullptr, false);
  if (truth.is_discarded() || !truth.contains("subsidence") || !truth["subsidence"].is_array() ||
      truth["subsidence"].empty())
    throw CommandError(file + ": subsidence: none (survey the later epoch with --subsidence)");
  nlohmann::json bowls = nlohmann::json::array();
  for (const nlohmann::json& bowl : truth["subsidence"]) {
    const bool complete = bowl.contains("volume_m3") && bowl["volume_m3"].is_number() &&
                          bowl.contains("max_depth_m") && bowl["max_depth_m"].is_number() &&
                          bowl.contains("radius_m") && bowl["radius_m"].is_number() &&
                          bowl.contains("centre_l") && bowl["centre_l"].is_array() &&
                          bowl["centre_l"].size() == 2;
    if (!complete)
      throw CommandError(
          file + ": subsidence: each bowl needs centre_l, radius_m, volume_m3, max_depth_m");
    const Eigen::Vector2d centre(bowl["centre_l"][0].get<double>(),
                                 bowl["centre_l"][1].get<double>());
    const double volume = bowl["volume_m3"].get<double>(),
                 depth = bowl["max_depth_m"].get<double>();
    const SubsidenceRegion* found =
        RegionNearest(change.regions, centre, bowl["radius_m"].get<double>());
    nlohmann::json j = {{"centre_l", {centre.x(), centre.y()}},
                        {"true_volume_m3", volume},
                        {"true_max_depth_m", depth},
                        {"found", found != nullptr}};
    if (found) {
      j["region"] = found->id;
      j["volume_m3"] = found->lowering.volume_m3;
      j["volume_sigma_m3"] = found->lowering.sigma_m3;
      j["volume_error"] = found->lowering.volume_m3 / volume - 1.0;
      j["max_depth_m"] = found->max_depth_m;
      j["max_depth_sigma_m"] = found->max_depth_sigma_m;
      j["max_depth_error_m"] = found->max_depth_m - depth;
      j["max_depth_error_in_sigma"] = (found->max_depth_m - depth) / found->max_depth_sigma_m;
    }
    bowls.push_back(j);
  }
  return {{"truth", truth_dir}, {"bowls", bowls}};
}

void Run(const DiffArgs& args) {
  const DemInput before = LoadDemInput(args.before);
  const DemInput after = LoadDemInput(args.after);
  const Result<ChangeResult> change =
      ComputeDemOfDifference({before.dem_file, before.dem, before.std_dev},
                             {after.dem_file, after.dem, after.std_dev}, args.options);
  if (!change) throw CommandError(change.error());
  nlohmann::json j = ChangeToJson(*change, args.options);
  j["before"] = {{"dem", before.dem_file}, {"std", before.std_file}};
  j["after"] = {{"dem", after.dem_file}, {"std", after.std_file}};
  if (!args.truth.empty()) j["evaluation"] = EvaluateAgainstTruth(*change, args.truth);
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (ec) throw CommandError(args.out + ": cannot create: " + ec.message());
  const std::filesystem::path out(args.out);
  if (Status s = WriteGeoTiff(change->dod, (out / "dod.tif").string()); !s)
    throw CommandError(s.error());
  if (Status s = WriteGeoTiff(change->dod_std, (out / "dod_std.tif").string()); !s)
    throw CommandError(s.error());
  const Raster shade = change->after_resampled ? after.dem.ResampledOnto(change->dod) : after.dem;
  std::optional<Eigen::Vector2d> mark;
  if (before.station_mark) mark = before.station_mark->head<2>();
  if (auto png =
          WritePngAtomically(RenderDodImage(*change, &shade, mark), (out / "dod.png").string());
      !png)
    throw CommandError(png.error());
  if (Status s = WriteFileAtomically((out / "subsidence.geojson").string(),
                                     SubsidenceGeoJson(*change).dump(1) + "\n");
      !s)
    throw CommandError(s.error());
  if (Status s = WriteFileAtomically((out / "change.json").string(), j.dump(2) + "\n"); !s)
    throw CommandError(s.error());
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  const ChangeResult& c = *change;
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
