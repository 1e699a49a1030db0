#include "station/diff_products.h"

#include <filesystem>
#include <optional>

#include "processing/change/change_json.h"
#include "processing/change/subsidence_regions.h"
#include "processing/io/atomic_file.h"
#include "processing/io/image_file.h"
#include "processing/products/dod_image.h"
#include "station/commands.h"
#include "station/dem_input.h"

namespace ts {
namespace {

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

}  // namespace

DiffProducts WriteDiffProducts(const std::string& before_input, const std::string& after_input,
                               const std::string& out_dir, const ChangeOptions& options,
                               const std::string& truth_dir) {
  const DemInput before = LoadDemInput(before_input);
  const DemInput after = LoadDemInput(after_input);
  const Result<ChangeResult> change =
      ComputeDemOfDifference({before.dem_file, before.dem, before.std_dev},
                             {after.dem_file, after.dem, after.std_dev}, options);
  if (!change) throw CommandError(change.error());
  nlohmann::json j = ChangeToJson(*change, options);
  j["before"] = {{"dem", before.dem_file}, {"std", before.std_file}};
  j["after"] = {{"dem", after.dem_file}, {"std", after.std_file}};
  if (!truth_dir.empty()) j["evaluation"] = EvaluateAgainstTruth(*change, truth_dir);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw CommandError(out_dir + ": cannot create: " + ec.message());
  const std::filesystem::path out(out_dir);
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
  return {*change, j};
}

}  // namespace ts
