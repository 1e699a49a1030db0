// The whole main job on every built-in scene (issue 6: "`survey --sim` runs end to end for
// every scene"; issue 21: on an estimated calibration): the real `topostation survey --sim
// --scene NAME` command, which calibrates the rig at a simulated control field, serves the
// simulated station, captures the 12 pairs (and the upper poses) over the real drivers with
// the daemon's plan and exposure control, processes them with the stage self-calibrated on
// the panorama's seams and evaluates the DEM against the truth; then the same survey with the
// simulator's true calibration (`--true-calibration`), which isolates matching from
// calibration. Issue 21's targets compare the two: DEM RMSE within 10 %, coverage within 1
// point, and the terrain correction's error within 2 of its sigma; and the seams the
// self-calibrated stage leaves, 95 % within 2 of their predicted sigma. bench_dem processes
// stations the simulator renders directly; a capture differs from them in its exposures and
// noise, so the DEM targets are checked here too. `rough` has no DEM targets (none in the
// issue), nor have issue 22's landforms here (bench_dem has theirs). The survey matches each pair
// while the capture goes on (the incremental station): the products are timed from the last pair's
// commit.
//
// --seeds 1,2,3: the seeds of every scene (default 1; the seed also draws the rig); --only
// slope,forest: those scenes only.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "processing/io/raster.h"
#include "tests/bench/bench_table.h"
#include "tests/common/temp_dir.h"

namespace {

using namespace ts;

struct SceneTargets {
  const char* scene;
  std::optional<double> max_rmse_m;  // none: no targets
};

// The last line of JSON a command printed (the rest is what the libraries say on stderr).
nlohmann::json JsonLine(const std::string& command) {
  const testing::CommandOutput r = testing::RunCommand(command + " 2>&1");
  std::string json, line;
  std::istringstream lines(r.out);
  while (std::getline(lines, line))
    if (!line.empty() && line.front() == '{') json = line;
  if (r.exit_code != 0 || json.empty()) {
    std::fprintf(stderr, "%s failed:\n%s\n", command.c_str(), r.out.c_str());
    std::exit(1);
  }
  return nlohmann::json::parse(json);
}

// The summary line of `survey --sim ... --json`; the station in `out`, its truth beside it.
nlohmann::json Survey(const std::string& scene, uint64_t seed, const std::string& extra,
                      const std::string& out) {
  return JsonLine(std::string(TS_TOPOSTATION_EXE) + " survey --sim --scene " + scene + " --seed " +
                  std::to_string(seed) + " " + extra + " --out " + out + " --json");
}

std::string AtMost(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "<= %.2f", v);
  return s;
}

// RMS of the DEM's error over the cells it has in `mask`'s turned footprint (both each in their
// own station frame, `turn_deg` apart), against the truth turned and lifted (`lift_m`) into its
// frame. The mask is taken by the nearest cell: bilinear sampling would drop the cells beside
// every gap of the mask and so the edges where a DEM's error is largest.
double RmseWithin(const Raster& dem, const Raster& mask, const Raster& truth, double turn_deg,
                  double lift_m, double mask_turn_deg) {
  const Raster truth_here = truth.ResampledOnto(dem, turn_deg, lift_m);
  const Raster mask_here =
      mask.ResampledOnto(dem, mask_turn_deg, 0.0, Raster::Sampling::kNearestCell);
  double sum = 0.0;
  int n = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      if (!Raster::IsNoData(dem.at(r, c)) && !Raster::IsNoData(truth_here.at(r, c)) &&
          !Raster::IsNoData(mask_here.at(r, c))) {
        sum += std::pow(dem.at(r, c) - truth_here.at(r, c), 2);
        ++n;
      }
  return n ? std::sqrt(sum / n) : NAN;
}

// The two surveys' DEM RMSE on the ground both cover (each on its own grid): what the
// calibration changes, without the cells only one of them reached.
double CommonRmseRatio(const std::string& estimated, const std::string& truth_calibrated,
                       const std::string& truth_dir, const nlohmann::json& evaluation) {
  const Raster e = ReadGeoTiff(estimated + "/products/dem.tif").value();
  const Raster t = ReadGeoTiff(truth_calibrated + "/products/dem.tif").value();
  const Raster truth = ReadGeoTiff(truth_dir + "/dem.tif").value();
  const double turn_deg = evaluation["azimuth_datum_deg"].get<double>();
  const double lift_m = evaluation["height_datum_m"].get<double>();
  return RmseWithin(e, t, truth, turn_deg, lift_m, turn_deg) /
         RmseWithin(t, e, truth, 0.0, 0.0, -turn_deg);
}

// The estimated survey's own pairs processed with the true calibration (and the station's
// true levelling): what the calibration alone changes. Two surveys differ also in what they
// captured: the upper poses follow from the row's matching, which the calibration moves, and a
// share near the rule's threshold turns one azimuth's upper pose into another's.
nlohmann::json SameImagesTrueCalibration(const std::string& estimated, const std::string& truth,
                                         const std::string& copy) {
  std::filesystem::copy(estimated, copy, std::filesystem::copy_options::recursive);
  std::filesystem::remove_all(copy + "/products");
  const std::string exe = TS_TOPOSTATION_EXE;
  JsonLine(exe + " process " + copy + " --calibration " + truth +
           "/calibration.yaml --set-up-from-calibration --json");
  return JsonLine(exe + " evaluate " + copy + " --truth " + truth + " --json");
}

void SurveyScene(const SceneTargets& t, uint64_t seed, bench::Table* table) {
  testing::TempDir dir;
  const nlohmann::json j = Survey(t.scene, seed, "", dir / "estimated");
  const nlohmann::json truth = Survey(t.scene, seed, "--true-calibration", dir / "true");
  const nlohmann::json same =
      SameImagesTrueCalibration(dir / "estimated", dir / "estimated-truth", dir / "same-images");
  const nlohmann::json& e = j["evaluation"];
  const nlohmann::json& et = truth["evaluation"];
  const std::string s = std::string(t.scene) + " s" + std::to_string(seed) + ": ";
  const double rmse = e["dem_rmse_m"].get<double>(), cov30 = e["coverage_30m"].get<double>(),
               square = e["coverage_60m_square"].get<double>();
  const double rmse_true = et["dem_rmse_m"].get<double>(),
               cov30_true = et["coverage_30m"].get<double>();
  table->Add({s + "survey, calibration to evaluation", j["survey_s"].get<double>(), "s", ""});
  table->Add({s + "capture", j["capture_s"].get<double>(), "s", ""});
  // Each pair is matched while the stage moves on: what the operator waits for after the last
  // pair is committed is the station-wide steps (issue 19: at most 1 s), here with the rig's
  // self-calibration; with the true calibration the rig is only checked.
  const double after = j["products_after_last_pair_s"].get<double>();
  table->Add({s + "products after the last pair", after, "s", "<= 1.0", after <= 1.0});
  table->Add({s + "  the same, true calibration", truth["products_after_last_pair_s"].get<double>(),
              "s", ""});
  // Issue 6's DEM targets are for each scene as the simulator builds it by default (seed 1);
  // issue 21's, which compare the calibrations, hold on every seed.
  if (t.max_rmse_m && seed == 1) {
    table->Add({s + "DEM RMSE", rmse, "m", AtMost(*t.max_rmse_m), rmse <= *t.max_rmse_m});
    table->Add({s + "coverage within 30 m", cov30, "", ">= 0.95", cov30 >= 0.95});
    table->Add({s + "coverage of the 60 m square", square, "", ">= 0.85", square >= 0.85});
  } else {
    table->Add({s + "DEM RMSE", rmse, "m", ""});
    table->Add({s + "coverage within 30 m", cov30, "", ""});
    table->Add({s + "coverage of the 60 m square", square, "", ""});
  }
  table->Add({s + "  DEM RMSE, true calibration", rmse_true, "m", ""});
  table->Add({s + "DEM RMSE, estimated / true", rmse / rmse_true, "", "<= 1.10",
              rmse <= 1.10 * rmse_true});
  table->Add({s + "  the same on the cells both cover",
              CommonRmseRatio(dir / "estimated", dir / "true", dir / "estimated-truth", e), "",
              ""});
  table->Add({s + "coverage 30 m, estimated - true", cov30 - cov30_true, "", ">= -0.01",
              cov30 - cov30_true >= -0.01});
  const double rmse_same = same["dem_rmse_m"].get<double>();
  const double cov30_same = same["coverage_30m"].get<double>();
  table->Add({s + "  DEM RMSE, estimated / true on the same images", rmse / rmse_same, "", ""});
  // The calibration's effect alone: the same images, on the cells both DEMs reach (where one
  // reaches farther its extra cells carry the error of ground nobody saw well).
  table->Add({s + "  the same images on the cells both cover",
              CommonRmseRatio(dir / "estimated", dir / "same-images", dir / "estimated-truth", e),
              "", ""});
  table->Add(
      {s + "  coverage 30 m, estimated - true on the same images", cov30 - cov30_same, "", ""});
  // Issue 21: the seams the stage self-calibrated on the panorama leaves (report.json's rig).
  std::ifstream report_file(dir / "estimated/products/report.json");
  const double seams =
      nlohmann::json::parse(report_file)["rig"]["seams"]["after"]["within_2_sigma"];
  table->Add({s + "seams after, within 2 sigma", seams, "", ">= 0.95", seams >= 0.95});
  const double tc_error = e["terrain_correction_error_mgal"].get<double>();
  const double tc_sigma = e["terrain_correction_sigma_mgal"].get<double>();
  table->Add({s + "terrain correction error / sigma", std::abs(tc_error) / tc_sigma, "", "<= 2.0",
              std::abs(tc_error) <= 2.0 * tc_sigma});
  table->Add({s + "DEM RMS error/std", e["std_ratio_rms"].get<double>(), "", ""});
}

}  // namespace

int main(int argc, char** argv) {
  bench::Table table(
      "survey --sim on every scene, estimated calibration beside the true one: capture over "
      "the real drivers to DEM");
  std::vector<uint64_t> seeds = bench::SeedsArgument(argc, argv);
  if (seeds.empty()) seeds.push_back(1);
  for (uint64_t seed : seeds)
    for (const SceneTargets& t :
         {SceneTargets{"flat", 0.10}, SceneTargets{"hills", 0.20}, SceneTargets{"slope", 0.35},
          SceneTargets{"forest", 0.35}, SceneTargets{"rough", std::nullopt},
          // Issue 22's landforms: its DEM targets are in bench_dem; here the survey's.
          SceneTargets{"embankment", std::nullopt}, SceneTargets{"terraces", std::nullopt},
          SceneTargets{"foot", std::nullopt}, SceneTargets{"ridge", std::nullopt},
          SceneTargets{"badlands", std::nullopt}})
      if (bench::Wanted(argc, argv, t.scene)) SurveyScene(t, seed, &table);
  return table.Finish(argc, argv);
}
