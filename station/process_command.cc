// topostation process STATION | evaluate STATION --truth DIR | ground-filter IN --out OUT:
// a station's products from its raw pairs, their error against the simulator's truth, and
// the ground filter for any point cloud.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <memory>

#include "processing/cloud/grid_index.h"
#include "processing/cloud/ground_filter.h"
#include "processing/dem/dem_evaluation.h"
#include "processing/gravity/terrain_correction.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/point_cloud_file.h"
#include "processing/io/raster.h"
#include "station/commands.h"
#include "station/dem_input.h"
#include "station/option_flags.h"
#include "station/progress_display.h"

namespace ts {
namespace {

struct ProcessArgs {
  std::string station;
  ProcessOptions options;
  std::vector<std::string> set;  // NAME=VALUE, any declared option
  bool json = false;
};

struct EvaluateArgs {
  std::string station;
  std::string truth;
  bool json = false;
};

struct GroundFilterArgs {
  std::string in;
  std::string out;
  GroundFilterOptions options;
};

void RunGroundFilter(const GroundFilterArgs& args) {
  std::string why;
  if (!args.options.Check(&why)) throw CommandError("ground-filter: " + why);
  Result<std::vector<Eigen::Vector3d>> points = ReadPointCloudXyz(args.in);
  if (!points) throw CommandError(points.error());
  // The filter grids the cloud's extent: a cloud whose points lie kilometres apart (or a
  // coordinate of 3e38) would need more cells than memory holds.
  constexpr double kMaxCells = 50e6;  // an airborne tile of 7 x 7 km at 1 m
  const double cells = GridIndex::CellsFor(*points, args.options.cell_m);
  if (cells == 0.0) throw CommandError(args.in + ": no point with finite coordinates");
  if (cells > kMaxCells)
    throw CommandError(args.in + ": the points lie too far apart for the ground filter's grid " +
                       "(more than " + OptionNumberText(kMaxCells) + " cells of " +
                       OptionNumberText(args.options.cell_m) +
                       " m): corrupt coordinates, or a cloud to cut into tiles");
  const GroundFilterResult r = FilterGround(*points, args.options);
  std::vector<Eigen::Vector3d> ground;
  for (size_t i = 0; i < points->size(); ++i)
    if (r.ground[i]) ground.push_back((*points)[i]);
  if (Status s = WritePly(args.out, ground); !s) throw CommandError(s.error());
  std::printf("%s: %zu of %zu points are ground\n", args.out.c_str(), ground.size(),
              points->size());
}

// The progress of a process job on the display (nothing when it is disabled).
ProcessControl ProgressControl(ProgressDisplay* display) {
  ProcessControl control;
  if (display->enabled())
    control.progress = [display](const ProcessProgress& p) {
      if (p.step == "matching" && p.pairs_total > 0)
        display->Count("process: pair", p.pairs_done, p.pairs_total);
      else
        display->Step("process", p.step, p.step_number, p.step_count);
    };
  return control;
}

}  // namespace

void PrintProcessSummary(const std::string& station, const nlohmann::json& r) {
  if (r["terrain_correction_mgal"].is_number())
    std::printf("%s: terrain correction %.4f +- %.4f mGal\n", station.c_str(),
                r["terrain_correction_mgal"].get<double>(),
                r["terrain_correction_sigma_mgal"].get<double>());
  else
    std::printf("%s: terrain correction unusable: %s\n", station.c_str(),
                r.value("unusable_because", std::string("?")).c_str());
  std::printf(
      "%s: %d points, %d ground, DEM %s (%.0f %% of the cells within 30 m, %.0f %% of "
      "the square) in %.1f s; products in %s/products\n",
      station.c_str(), r["counts"]["points"].get<int>(), r["counts"]["ground"].get<int>(),
      r["variogram"]["model"].get<std::string>().c_str(),
      100 * r["dem"]["coverage_30m"].get<double>(), 100 * r["dem"]["coverage_square"].get<double>(),
      r["wall_s"].get<double>(), station.c_str());
}

nlohmann::json ProcessOrThrow(const std::string& station, const ProcessOptions& options,
                              bool show_progress) {
  ProgressDisplay display(show_progress);
  Result<ProcessResult> result = ProcessStation(station, options, ProgressControl(&display));
  display.Clear();
  if (!result) throw CommandError(result.error());
  return result->report;
}

nlohmann::json FinishOrThrow(StationProcessor* processor) {
  Result<ProcessResult> result = processor->Finish();
  if (!result) throw CommandError(result.error());
  return result->report;
}

void PrintEvaluation(const nlohmann::json& j) {
  std::printf(
      "DEM against truth: RMSE %.3f m (%.3f m within 30 m), bias %+.3f m, p95 |error| %.3f m; "
      "coverage %.1f %% within 30 m, %.1f %% of the 60 m square\n",
      j["dem_rmse_m"].get<double>(),
      j["dem_rmse_30m_m"].is_number() ? j["dem_rmse_30m_m"].get<double>() : NAN,
      j["dem_bias_m"].get<double>(), j["dem_p95_abs_m"].get<double>(),
      100 * j["coverage_30m"].get<double>(), 100 * j["coverage_60m_square"].get<double>());
  if (j["std_ratio_rms"].is_number())
    std::printf("DEM std against its true errors: RMS error/std %.2f, %.1f %% within 2 std\n",
                j["std_ratio_rms"].get<double>(), 100 * j["within_2std"].get<double>());
  std::printf(
      "terrain correction %.4f +- %.4f mGal; from the true DEM %.4f mGal (error %+.4f mGal)\n",
      j["terrain_correction_mgal"].get<double>(), j["terrain_correction_sigma_mgal"].get<double>(),
      j["terrain_correction_true_mgal"].get<double>(),
      j["terrain_correction_error_mgal"].get<double>());
}

// The station frame's datums, which no image shows, as the station was processed
// (products/report.json's calibration): the pan zero (its azimuth) and the tilt axis's height
// (its origin lies that far under the tilt axis).
struct ProcessedDatums {
  double pan_zero_deg = 0.0;
  double tilt_axis_height_m = 0.0;
};

ProcessedDatums ReadProcessedDatums(const std::string& station) {
  const std::string file = station + "/products/report.json";
  std::ifstream in(file);
  const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
  const auto datum = [&](const char* key) {
    const nlohmann::json* value =
        report.is_object() && report.contains("calibration") && report["calibration"].contains(key)
            ? &report["calibration"][key]
            : nullptr;
    if (!value || !value->is_number())
      throw CommandError(file + ": calibration." + key + ": missing (process the station again)");
    return value->get<double>();
  };
  return {datum("pan_zero_deg"), datum("tilt_axis_height_m")};
}

// The station's own terrain correction and its sigma (products/terrain_correction.json): every
// cell of the square, also those the DEM has no value for.
std::pair<double, double> StationTerrainCorrection(const std::string& station) {
  const std::string file = station + "/products/terrain_correction.json";
  std::ifstream in(file);
  const nlohmann::json tc = nlohmann::json::parse(in, nullptr, false);
  if (tc.is_object() && tc.value("verdict", "") == "unusable")
    throw CommandError(file + ": the terrain correction is unusable: " +
                       tc.value("unusable_because", std::string("?")));
  for (const char* field : {"terrain_correction_mgal", "sigma_mgal"})
    if (!tc.is_object() || !tc.contains(field) || !tc[field].is_number())
      throw CommandError(file + ": " + field + ": missing (process the station again)");
  return {tc["terrain_correction_mgal"].get<double>(), tc["sigma_mgal"].get<double>()};
}

nlohmann::json EvaluateOrThrow(const std::string& station, const std::string& truth_dir) {
  const DemInput in = LoadDemInput(station);
  const Raster& dem = in.dem;
  const Raster* std_dev = in.std_dev ? &*in.std_dev : nullptr;
  if (!dem.crs_wkt.empty())
    throw CommandError(station +
                       "/products/dem.tif: georeferenced; the truth is in the station "
                       "frame (process without --gcps to evaluate)");
  const Result<Raster> truth = ReadGeoTiff(truth_dir + "/dem.tif");
  if (!truth) throw CommandError(truth.error());
  const Result<Calibration> calibration = LoadCalibrationYaml(truth_dir + "/calibration.yaml");
  if (!calibration) throw CommandError(calibration.error());
  const Eigen::Vector2d station_xy = calibration->stage.StationMarkInL().head<2>();
  // The station frame's azimuth is the pan encoder's zero of the calibration it was processed
  // with, which no panorama shows and the terrain correction does not depend on: the truth is
  // compared turned into it.
  const ProcessedDatums processed = ReadProcessedDatums(station);
  const double turn_deg = calibration->stage.pan_zero_deg - processed.pan_zero_deg;
  // Its origin lies the calibration's tilt-axis height under the tilt axis, which no image
  // shows either (it lifts every view alike): the two frames agree at the tilt axis, and the
  // truth is lifted into the processed one. The mark hangs from the tilt axis by the taped
  // instrument height in both.
  const double lift_m = processed.tilt_axis_height_m - calibration->stage.tilt_axis_offset_m.z();
  const Raster truth_on_grid = truth->ResampledOnto(dem, turn_deg, lift_m);
  const DemEvaluation e = EvaluateDem(dem, truth_on_grid, station_xy, std_dev);
  if (e.cells_compared == 0)
    throw CommandError(station + "/products/dem.tif: no cell overlaps the truth DEM " + truth_dir +
                       "/dem.tif");
  nlohmann::json j = e.ToJson();
  j["truth"] = truth_dir;
  j["azimuth_datum_deg"] = turn_deg;
  j["height_datum_m"] = lift_m;
  // The terrain correction from this DEM against the one from the true bare earth on the
  // same grid, both at the true mark.
  const Eigen::Vector3d mark = calibration->stage.StationMarkInL() + Eigen::Vector3d(0, 0, lift_m);
  const TerrainCorrectionOptions tc_options;
  const auto [ours, sigma] = StationTerrainCorrection(station);
  const TerrainCorrection truth_tc =
      ComputeTerrainCorrection(truth_on_grid, nullptr, mark, tc_options);
  j["terrain_correction_mgal"] = ours;
  j["terrain_correction_sigma_mgal"] = sigma;
  j["terrain_correction_true_mgal"] = truth_tc.total_mgal;
  j["terrain_correction_error_mgal"] = ours - truth_tc.total_mgal;
  if (Status s = WriteFileAtomically(station + "/products/evaluation.json", j.dump(2) + "\n"); !s)
    throw CommandError(s.error());
  return j;
}

void AddProcessCommands(CLI::App& app) {
  auto process = std::make_shared<ProcessArgs>();
  CLI::App* p = app.add_subcommand("process", "Turn a captured station into its DEM and products");
  p->add_option("station", process->station, "station directory")->required();
  AddDeclaredOption(p, "--calibration", process->options, "calibration_file");
  AddDeclaredOption(p, "--set-up-from-calibration", process->options,
                    "set_up_from_calibration_file");
  AddDeclaredOption(p, "--gcps", process->options, "gcp_file");
  AddDeclaredOption(p, "--self-calibrate-rig", process->options, "self_calibrate_rig");
  AddDeclaredOption(p, "--half-size-m", process->options, "dem_half_size_m");
  AddDeclaredOption(p, "--max-distance-m", process->options, "kriging.max_distance_m");
  AddDeclaredOption(p, "--object-shadow-reach-m", process->options,
                    "horizon.object_shadow_reach_m");
  p->add_option("--set", process->set,
                "NAME=VALUE: any option of process (report.json's \"options\" names them), "
                "e.g. ground.slope=0.1; repeatable");
  p->add_flag("--json", process->json, "print the report as JSON");
  p->callback([process] {
    for (const std::string& assignment : process->set)
      if (const std::string error = SetDeclaredOption(process->options, assignment); !error.empty())
        throw CommandError(error);
    const nlohmann::json r = ProcessOrThrow(process->station, process->options,
                                            ::isatty(STDERR_FILENO) && !process->json);
    if (process->json)
      std::printf("%s\n", r.dump().c_str());
    else
      PrintProcessSummary(process->station, r);
  });

  auto evaluate = std::make_shared<EvaluateArgs>();
  CLI::App* e = app.add_subcommand(
      "evaluate",
      "DEM error of a processed station against ground truth (products/evaluation.json)");
  e->add_option("station", evaluate->station, "processed station directory")->required();
  e->add_option("--truth", evaluate->truth, "truth directory of the simulator")->required();
  e->add_flag("--json", evaluate->json, "print the evaluation as JSON");
  e->callback([evaluate] {
    const nlohmann::json j = EvaluateOrThrow(evaluate->station, evaluate->truth);
    if (evaluate->json) {
      std::printf("%s\n", j.dump().c_str());
    } else {
      PrintEvaluation(j);
    }
  });

  auto ground = std::make_shared<GroundFilterArgs>();
  CLI::App* g = app.add_subcommand(
      "ground-filter",
      "Keep the bare-earth points of a cloud (.pcd or .ply), coordinates unchanged");
  g->add_option("in", ground->in, "input cloud (.pcd or .ply)")->required();
  g->add_option("--out", ground->out, "output PLY of the ground points")->required();
  AddDeclaredOption(g, "--cell-m", ground->options, "cell_m");
  AddDeclaredOption(g, "--slope", ground->options, "slope");
  AddDeclaredOption(g, "--window-m", ground->options, "max_window_m");
  AddDeclaredOption(g, "--threshold-m", ground->options, "elevation_threshold_m");
  g->callback([ground] { RunGroundFilter(*ground); });
}

}  // namespace ts
