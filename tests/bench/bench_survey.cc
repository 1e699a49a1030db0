// The whole main job on every built-in scene (issue 6: "`survey --sim` runs end to end for
// every scene"): the real `topostation survey --sim --scene NAME` command, which serves the
// simulated station, captures the 12 pairs (and the upper poses) over the real drivers with the
// daemon's plan and exposure control, processes them with the true calibration and evaluates
// the DEM against the truth. bench_dem processes stations the simulator renders directly; a
// capture differs from them in its exposures and noise, and its DEM by a few points of
// coverage, so the DEM targets are checked here too. `rough` has no targets (none in the
// issue); its rows show how the pipeline does on rocks, gullies and steps. The survey matches
// each pair while the capture goes on (the incremental station): the products are timed from
// the last pair's commit.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "tests/bench/bench_table.h"
#include "tests/common/temp_dir.h"

namespace {

using namespace ts;

struct SceneTargets {
  const char* scene;
  std::optional<double> max_rmse_m;  // none: no targets
};

void Survey(const SceneTargets& t, bench::Table* table) {
  testing::TempDir dir;
  const std::string out = dir / "station";
  const testing::CommandOutput r =
      testing::RunCommand(std::string(TS_TOPOSTATION_EXE) + " survey --sim --scene " + t.scene +
                          " --out " + out + " --json 2>&1");
  // Its summary is the one line of JSON; the rest is what the libraries say on stderr.
  std::string summary, line;
  std::istringstream lines(r.out);
  while (std::getline(lines, line))
    if (!line.empty() && line.front() == '{') summary = line;
  if (r.exit_code != 0 || summary.empty()) {
    std::fprintf(stderr, "survey of %s failed:\n%s\n", t.scene, r.out.c_str());
    std::exit(1);
  }
  const nlohmann::json j = nlohmann::json::parse(summary);
  const nlohmann::json& e = j["evaluation"];
  const std::string s = std::string(t.scene) + ": ";
  const double rmse = e["dem_rmse_m"].get<double>(), cov30 = e["coverage_30m"].get<double>(),
               square = e["coverage_60m_square"].get<double>();
  table->Add({s + "survey, capture to evaluation", j["survey_s"].get<double>(), "s", ""});
  table->Add({s + "capture", j["capture_s"].get<double>(), "s", ""});
  // Each pair is matched while the stage moves on: what the operator waits for after the last
  // pair is committed is the station-wide steps (issue 19: at most 1 s).
  const double after = j["products_after_last_pair_s"].get<double>();
  table->Add({s + "products after the last pair", after, "s", "<= 1.0", after <= 1.0});
  table->Add(
      {s + "station-wide steps (process after capture)", j["process_s"].get<double>(), "s", ""});
  if (t.max_rmse_m) {
    char target[32];
    std::snprintf(target, sizeof target, "<= %.2f", *t.max_rmse_m);
    table->Add({s + "DEM RMSE", rmse, "m", target, rmse <= *t.max_rmse_m});
    table->Add({s + "coverage within 30 m", cov30, "", ">= 0.95", cov30 >= 0.95});
    table->Add({s + "coverage of the 60 m square", square, "", ">= 0.85", square >= 0.85});
  } else {
    table->Add({s + "DEM RMSE", rmse, "m", ""});
    table->Add({s + "coverage within 30 m", cov30, "", ""});
    table->Add({s + "coverage of the 60 m square", square, "", ""});
  }
  table->Add({s + "DEM p95 |error|", e["dem_p95_abs_m"].get<double>(), "m", ""});
  table->Add({s + "terrain correction error", e["terrain_correction_error_mgal"].get<double>(),
              "mGal", ""});
}

}  // namespace

int main(int argc, char** argv) {
  bench::Table table("survey --sim on every scene: capture over the real drivers to DEM");
  for (const SceneTargets& t :
       {SceneTargets{"flat", 0.10}, SceneTargets{"hills", 0.20}, SceneTargets{"slope", 0.35},
        SceneTargets{"forest", 0.35}, SceneTargets{"rough", std::nullopt}})
    Survey(t, &table);
  return table.Finish(argc, argv);
}
