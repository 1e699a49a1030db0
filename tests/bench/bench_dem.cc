// From points to DEM (issue 6), in one table:
//  - each scene (flat, hills, slope, forest): a station rendered by the simulator (12 full-
//    resolution pairs, as `sim render` writes them) is processed by the real `topostation
//    process` command with the true calibration: its wall time and peak memory (from its
//    report.json), the DEM's RMSE over cells with data in the 60 m square against the true
//    bare earth, its coverage, and kriging against nearest-neighbour interpolation of the same
//    ground points; on forest also the share of object points (> 0.5 m above the true
//    ground) that the ground filter removed; the terrain correction from the processed DEM
//    against the one from the true DEM (and its speed);
//  - on flat and hills a second epoch (another sun, new noise, a 0.5 m subsidence bowl where
//    the tripod sees it) processed the same way: the change detection's subsidence region
//    against the bowl (volume, deepest point in its sigma);
//  - beside the true calibration, the same station processed as a field team would (issue 21):
//    the rig calibrated at a simulated control field of the same rig (`calibrate stereo`, the
//    stage's design values, then `calibrate rig` on the session), `process --self-calibrate-rig`,
//    `evaluate` (in the station's own azimuth datum): DEM RMSE within 10 % of the true
//    calibration's, coverage within 1 point;
//  - the ISPRS filter-test samples: mean total error of our ground filter and, beside it,
//    PCL's progressive morphological filter with the PCL tutorial settings;
//  - with --seeds 2,3,...: hills and forest stations of other seeds (other sites of the same
//    kind), processed the same way: DEM RMSE, coverage and object points removed, without
//    targets (the targets are for the scenes as the simulator builds them by default).
//    They show how far what was tuned on one station carries to other sites;
//  - issue 22's landforms (embankment, terraces, foot, ridge, badlands), seed 1 or each of
//    --seeds: DEM RMSE, the std's honesty (also on each kind of cell alone: seen, unseen
//    under a line of sight, unseen beyond the lines; and the cells more than 10 std off, which
//    an honest std has none of, with the rest alone), cells standing above a line of sight
//    (sight_line_bound.h), the terrain correction's error against its sigma.
#include <pcl/filters/extract_indices.h>
#include <pcl/point_types.h>
#include <pcl/segmentation/progressive_morphological_filter.h>

#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "processing/change/dem_of_difference.h"
#include "processing/change/subsidence_regions.h"
#include "processing/cloud/ground_filter.h"
#include "processing/common/memory.h"
#include "processing/dem/dem_evaluation.h"
#include "processing/gravity/terrain_correction.h"
#include "processing/io/station_manifest.h"
#include "processing/pipeline/process_station.h"
#include "sim/calibration_field.h"
#include "sim/sim_station.h"
#include "station/field_session.h"
#include "tests/bench/bench_table.h"
#include "tests/bench/sight_line_bound.h"
#include "tests/common/isprs_sample.h"
#include "tests/common/temp_dir.h"

namespace {

using namespace ts;

struct SceneTargets {
  const char* scene;
  double max_rmse_m;
  double max_tc_error_mgal;
  std::optional<sim::Subsidence> bowl = std::nullopt;  // a second epoch with it
};

sim::Subsidence Bowl(double x, double y, double radius, double depth) {
  sim::Subsidence b;
  b.centre_m = {x, y};
  b.radius_m = radius;
  b.depth_m = depth;
  return b;
}

// The station of a scene rendered into dir/station and dir/truth.
std::shared_ptr<const sim::SimStation> Render(const sim::SimStationOptions& options,
                                              const std::string& station_dir,
                                              const std::string& truth_dir) {
  const auto station = *sim::BuildSimStation(options);
  if (Status s = sim::RenderStationDirectory(*station, sim::StationRenderOptions{}, station_dir,
                                             truth_dir);
      !s) {
    std::fprintf(stderr, "%s\n", s.error().c_str());
    std::exit(1);
  }
  return station;
}

// A later epoch with a bowl, against the processed first epoch `first`.
void SubsidenceEpoch(const char* scene, const sim::Subsidence& bowl, const ProcessResult& first,
                     bench::Table* table) {
  testing::TempDir dir;
  sim::SimStationOptions options;
  options.scene = scene;
  options.epoch = 2;
  options.subsidence = {bowl};
  options.sun_deg = {120.0, 40.0};
  Render(options, dir / "station", dir / "truth");
  ProcessOptions process;
  process.calibration_file = dir / "truth/calibration.yaml";
  process.set_up_from_calibration_file = true;
  const ProcessResult second = ProcessStation(dir / "station", process).value();
  const ChangeResult change = ComputeDemOfDifference({"epoch 1", first.dem, first.dem_std},
                                                     {"epoch 2", second.dem, second.dem_std})
                                  .value();
  const SubsidenceRegion* found = RegionNearest(change.regions, bowl.centre_m, bowl.radius_m);
  const std::string s = std::string(scene) + ": subsidence bowl ";
  if (!found) {
    table->Add({s + "found", 0.0, "", "1", false});
    return;
  }
  const double volume_error = found->lowering.volume_m3 / bowl.Volume() - 1.0;
  const double depth_in_sigma = (found->max_depth_m - bowl.depth_m) / found->max_depth_sigma_m;
  table->Add({s + "true volume", bowl.Volume(), "m3", ""});
  table->Add({s + "volume error", volume_error, "", "|.| <= 0.10", std::abs(volume_error) <= 0.1});
  table->Add({s + "depth error", found->max_depth_m - bowl.depth_m, "m", ""});
  table->Add(
      {s + "depth error / sigma", depth_in_sigma, "", "|.| <= 2", std::abs(depth_in_sigma) <= 2.0});
}

// `command` (this program's topostation), or the benchmark ends with its output.
std::string Run(const std::string& command) {
  const testing::CommandOutput r =
      testing::RunCommand(std::string(TS_TOPOSTATION_EXE) + " " + command + " 2>&1");
  if (r.exit_code != 0) {
    std::fprintf(stderr, "topostation %s failed:\n%s\n", command.c_str(), r.out.c_str());
    std::exit(1);
  }
  return r.out;
}

// The rendered station (a copy) processed on the calibration a field team would have: a
// control-field session of its rig, `calibrate stereo` with the stage's design values and
// `calibrate rig` on the same session (as survey --sim does), the stage self-calibrated on the
// station's seams. Against the true calibration's evaluation.
void EstimatedCalibration(const std::string& scene, const sim::SimStation& station,
                          const std::string& station_dir, const std::string& truth_dir,
                          const DemEvaluation& with_truth, bench::Table* table) {
  testing::TempDir dir;
  const std::string session = dir / "session", cameras = dir / "cameras.yaml",
                    cal = dir / "calibration.yaml";
  if (!sim::WriteFieldSession(station.rig, station.scene.seed, {}, session, dir / "session-truth"))
    std::exit(1);
  for (const std::vector<std::string>& command :
       FieldCalibrationCommands(SimulatedFieldSession(session), cameras, cal)) {
    std::string line;  // quoted: the globs are the command's own, not the shell's
    for (const std::string& arg : command) line += (line.empty() ? "'" : " '") + arg + "'";
    Run(line);
  }
  const std::string copy = dir / "station";
  std::filesystem::copy(station_dir, copy, std::filesystem::copy_options::recursive);
  std::filesystem::remove_all(copy + "/products");
  Run("process " + copy + " --calibration " + cal + " --self-calibrate-rig --json");
  const std::string out = Run("evaluate " + copy + " --truth " + truth_dir + " --json");
  const nlohmann::json e = nlohmann::json::parse(out.substr(out.rfind("\n{") + 1));
  const nlohmann::json report =
      nlohmann::json::parse(std::ifstream(copy + "/products/report.json"));
  const std::string s = scene + ", estimated calibration: ";
  const double rmse = e["dem_rmse_m"].get<double>(), cov30 = e["coverage_30m"].get<double>();
  table->Add({s + "DEM RMSE", rmse, "m", ""});
  table->Add({s + "DEM RMSE / true calibration's", rmse / with_truth.rmse_m, "", "<= 1.10",
              rmse <= 1.10 * with_truth.rmse_m});
  table->Add({s + "coverage 30 m - true calibration's", cov30 - with_truth.coverage_30m, "",
              ">= -0.01", cov30 - with_truth.coverage_30m >= -0.01});
  table->Add({s + "DEM RMS of error / kriging std", e["std_ratio_rms"].get<double>(), "", ""});
  const double tc_error = e["terrain_correction_error_mgal"].get<double>();
  const double tc_sigma = e["terrain_correction_sigma_mgal"].get<double>();
  table->Add({s + "terrain correction error / sigma", std::abs(tc_error) / tc_sigma, "", "<= 2.0",
              std::abs(tc_error) <= 2.0 * tc_sigma});
  table->Add({s + "seams within 2 sigma, after",
              report["rig"]["seams"]["after"]["within_2_sigma"].get<double>(), "", ""});
  table->Add({s + "process", report["wall_s"].get<double>(), "s", ""});
}

// Points more than 0.5 m above the true ground in the square, and how many of them the
// processing did not keep as ground.
struct ObjectPoints {
  double objects = 0, removed = 0;
  double Removed() const { return removed / objects; }
};
ObjectPoints CountObjectPoints(const sim::SimStation& station, const ProcessResult& r) {
  ObjectPoints o;
  for (size_t i = 0; i < r.cloud.size(); ++i) {
    if (r.point_class[i] == kOutsideDem) continue;
    const Eigen::Vector3d& p = r.cloud[i].position_m;
    if (p.z() - station.scene.TerrainHeight(p.x(), p.y()) <= 0.5) continue;
    ++o.objects;
    o.removed += r.point_class[i] != kGround;
  }
  return o;
}

void SimulatedSurvey(const SceneTargets& t, bench::Table* table) {
  testing::TempDir dir;
  const std::string station_dir = dir / "station", truth_dir = dir / "truth";
  sim::SimStationOptions options;
  options.scene = t.scene;
  const auto station = Render(options, station_dir, truth_dir);
  // The real command, for its wall time and peak memory.
  const std::string command =
      std::string(TS_TOPOSTATION_EXE) + " process " + station_dir + " --calibration " + truth_dir +
      "/calibration.yaml --set-up-from-calibration --json > " + (dir / "report.json");
  if (std::system(command.c_str()) != 0) std::exit(1);
  const nlohmann::json report =
      nlohmann::json::parse(std::ifstream(station_dir + "/products/report.json"));

  // The same processing in this process, to look at its points.
  ProcessOptions process;
  process.calibration_file = truth_dir + "/calibration.yaml";
  process.set_up_from_calibration_file = true;
  const ProcessResult r = ProcessStation(station_dir, process).value();
  const Raster truth = ReadGeoTiff(truth_dir + "/dem.tif").value();
  const Eigen::Vector2d mark = station->rig.truth.stage.StationMarkInL().head<2>();
  const DemEvaluation e = EvaluateDem(r.dem, truth, mark, &r.dem_std);

  // Nearest neighbour (kriging with one neighbour) on the same thinned ground points, in the
  // same cells (the kriged DEM reaches farther in the shadows of objects).
  KrigingPoints ground;
  for (size_t i = 0; i < r.cloud.size(); ++i)
    if (r.point_class[i] == kGround) ground.positions.push_back(r.cloud[i].position_m);
  KrigingOptions nearest_options = process.kriging;
  nearest_options.neighbours = 1;
  nearest_options.extrapolation_neighbours = 0;
  nearest_options.max_distance_m = process.horizon.KrigingReach(process.kriging.max_distance_m);
  Raster nearest = r.dem, unused;
  KrigeOnto(ThinPoints(ground, process.kriging.thin_cell_m), VariogramModel{}, nearest_options,
            &nearest, &unused);
  for (size_t i = 0; i < nearest.values.size(); ++i)
    if (Raster::IsNoData(r.dem.values[i])) nearest.values[i] = Raster::kNoData;
  const DemEvaluation n = EvaluateDem(nearest, truth, mark);

  const std::string s = std::string(t.scene) + ": ";
  char target[32];
  std::snprintf(target, sizeof target, "<= %.2f", t.max_rmse_m);
  table->Add({s + "DEM RMSE (kriging)", e.rmse_m, "m", target, e.rmse_m <= t.max_rmse_m});
  table->Add({s + "DEM RMSE (nearest neighbour)", n.rmse_m, "m", ""});
  table->Add({s + "DEM bias", e.bias_m, "m", ""});
  table->Add({s + "DEM p95 |error|", e.p95_abs_m, "m", ""});
  // How honest the kriging std is (1: exactly; objects left as ground make it too small).
  table->Add({s + "DEM RMS of error / kriging std", e.std_ratio_rms, "", ""});
  table->Add({s + "DEM cells with |error| <= 2 std", e.within_2std, "", ""});
  table->Add({s + "coverage within 30 m", e.coverage_30m, "", ">= 0.95", e.coverage_30m >= 0.95});
  table->Add({s + "coverage of the 60 m square", e.coverage_square, "", ">= 0.85",
              e.coverage_square >= 0.85});
  const double wall = report["wall_s"].get<double>();
  table->Add({s + "process (raw images to products)", wall, "s", "<= 3.5", wall <= 3.5});
  table->Add({s + "process peak memory", report["peak_memory_mib"].get<double>(), "MiB", ""});
  // Terrain correction from the processed DEM against the one from the true DEM on the same
  // grid, both at the true mark.
  const Eigen::Vector3d mark3 = station->rig.truth.stage.StationMarkInL();
  const double tc_true =
      ComputeTerrainCorrection(truth.ResampledOnto(r.dem), nullptr, mark3, {}).total_mgal;
  const double tc_error = r.terrain_correction.total_mgal - tc_true;
  std::snprintf(target, sizeof target, "|.| <= %.2f", t.max_tc_error_mgal);
  table->Add({s + "terrain correction (true DEM)", tc_true, "mGal", ""});
  table->Add({s + "terrain correction error", tc_error, "mGal", target,
              std::abs(tc_error) <= t.max_tc_error_mgal});
  table->Add({s + "terrain correction sigma", r.terrain_correction.sigma_mgal, "mGal", ""});
  if (std::string(t.scene) == "hills") {  // speed: the 60 m square at 1 m with refinement
    const int runs = 20;
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < runs; ++k) ComputeTerrainCorrection(r.dem, &r.dem_std, mark3, {});
    const double ms =
        1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / runs;
    table->Add({"terrain correction of a 60 x 60 DEM (one core)", ms, "ms", "<= 50", ms <= 50});
  }
  EstimatedCalibration(t.scene, *station, station_dir, truth_dir, e, table);
  if (t.bowl) SubsidenceEpoch(t.scene, *t.bowl, r, table);
  if (std::string(t.scene) == "forest") {
    const ObjectPoints o = CountObjectPoints(*station, r);
    table->Add({s + "object points (> 0.5 m) in the square", o.objects, "", ""});
    table->Add(
        {s + "share of object points removed", o.Removed(), "", ">= 0.98", o.Removed() >= 0.98});
  }
}

std::vector<uint8_t> PclMorphologicalFilter(const std::vector<Eigen::Vector3d>& points) {
  // PCL's tutorial settings; coordinates about their mean (float precision).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p / points.size();
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (const auto& p : points) {
    const Eigen::Vector3d q = p - mean;
    cloud->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  pcl::ProgressiveMorphologicalFilter<pcl::PointXYZ> pmf;
  pmf.setInputCloud(cloud);
  pmf.setMaxWindowSize(20);
  pmf.setSlope(1.0f);
  pmf.setInitialDistance(0.5f);
  pmf.setMaxDistance(3.0f);
  pcl::Indices ground;
  pmf.extract(ground);
  std::vector<uint8_t> flags(points.size(), 0);
  for (int i : ground) flags[i] = 1;
  return flags;
}

void IsprsSamples(bench::Table* table) {
  double ours = 0, pcl = 0;
  for (const std::string& name : testing::kIsprsSamples) {
    const testing::IsprsSample s = testing::LoadIsprsSample(name);
    const testing::FilterErrors a =
        testing::ClassificationErrors(s.reference_ground, FilterGround(s.points, {}).ground);
    const testing::FilterErrors b =
        testing::ClassificationErrors(s.reference_ground, PclMorphologicalFilter(s.points));
    table->Add({"ISPRS " + name + ": total error, ours", a.total, "", ""});
    table->Add({"ISPRS " + name + ": total error, PCL PMF", b.total, "", ""});
    ours += a.total / testing::kIsprsSamples.size();
    pcl += b.total / testing::kIsprsSamples.size();
  }
  table->Add({"ISPRS mean total error, ours", ours, "", "<= 0.06", ours <= 0.06});
  table->Add({"ISPRS mean total error, PCL PMF (tutorial)", pcl, "", ""});
}

// A station of a scene and seed rendered into dir/station (truth in dir/truth) and processed
// there with the true calibration, its DEM evaluated against the true bare earth.
struct TrueSite {
  std::shared_ptr<const sim::SimStation> station;
  ProcessResult result;
  Raster truth;
  DemEvaluation evaluation;
};

TrueSite ProcessTrueSite(const char* scene, uint64_t seed, const testing::TempDir& dir) {
  sim::SimStationOptions options;
  options.scene = scene;
  options.seed = seed;
  TrueSite site;
  site.station = Render(options, dir / "station", dir / "truth");
  ProcessOptions process;
  process.calibration_file = dir / "truth/calibration.yaml";
  process.set_up_from_calibration_file = true;
  site.result = ProcessStation(dir / "station", process).value();
  site.truth = ReadGeoTiff(dir / "truth/dem.tif").value();
  const Eigen::Vector2d mark = site.station->rig.truth.stage.StationMarkInL().head<2>();
  site.evaluation = EvaluateDem(site.result.dem, site.truth, mark, &site.result.dem_std);
  return site;
}

// hills and forest at another seed: informational rows.
void OtherSite(const char* scene, uint64_t seed, bench::Table* table) {
  testing::TempDir dir;
  const TrueSite site = ProcessTrueSite(scene, seed, dir);
  const auto& [station, r, truth, e] = site;
  const std::string s = std::string(scene) + " seed " + std::to_string(seed) + ": ";
  table->Add({s + "DEM RMSE", e.rmse_m, "m", ""});
  table->Add({s + "coverage within 30 m", e.coverage_30m, "", ""});
  if (!station->scene.objects.empty())
    table->Add(
        {s + "share of object points removed", CountObjectPoints(*station, r).Removed(), "", ""});
}

// Where the std's dishonesty lies: the DEM evaluated on each kind of cell alone. Seen: a
// ground point in it. Unseen under a line: a line of sight passed over it to farther ground
// (products/dem_ceiling.tif), which bounds it from above and, by its landing, below. Unseen
// beyond the lines: no line passed over it (the ground past the last seen in its azimuths,
// bounded by nothing but the turn of the seen ground).
struct CellKindHonesty {
  const char* name;
  DemEvaluation evaluation;
  double share_of_squares = 0.0;  // of the sum over all cells of (error / std)^2
};

std::vector<CellKindHonesty> HonestyByCellKind(const TrueSite& site, const Raster& ceiling,
                                               const Eigen::Vector2d& mark) {
  const ProcessResult& r = site.result;
  std::vector<uint8_t> seen(static_cast<size_t>(r.dem.rows) * r.dem.cols, 0);
  for (size_t i = 0; i < r.cloud.size(); ++i) {
    int row, col;
    const Eigen::Vector3d& p = r.cloud[i].position_m;
    if (r.point_class[i] == kGround && r.dem.CellOf(p.x(), p.y(), &row, &col))
      seen[static_cast<size_t>(row) * r.dem.cols + col] = 1;
  }
  auto kind_of = [&](int row, int col) {
    if (seen[static_cast<size_t>(row) * r.dem.cols + col]) return 0;
    return Raster::IsNoData(ceiling.at(row, col)) ? 2 : 1;
  };
  const char* names[] = {"seen", "unseen under a line", "unseen beyond the lines"};
  const DemEvaluation& all = site.evaluation;
  const double all_squares = all.cells_compared * all.std_ratio_rms * all.std_ratio_rms;
  std::vector<CellKindHonesty> kinds;
  for (int kind = 0; kind < 3; ++kind) {
    Raster only = r.dem;
    for (int row = 0; row < only.rows; ++row)
      for (int col = 0; col < only.cols; ++col)
        if (kind_of(row, col) != kind) only.at(row, col) = Raster::kNoData;
    CellKindHonesty k{names[kind], EvaluateDem(only, site.truth, mark, &r.dem_std)};
    if (k.evaluation.cells_compared > 0 && all_squares > 0.0)
      k.share_of_squares = k.evaluation.cells_compared * k.evaluation.std_ratio_rms *
                           k.evaluation.std_ratio_rms / all_squares;
    kinds.push_back(k);
  }
  return kinds;
}

// Whether the std misses all over or in a few cells: the cells more than 10 std off (a DEM
// whose std is honest has none), their share of the sum of (error / std)^2, and the rest
// evaluated alone. A tail is matches that agree with each other and are wrong (a lip blended
// with the ground behind it), not a std too small everywhere.
struct StdTail {
  int cells = 0;
  double share_of_squares = 0.0;
  DemEvaluation rest;
};

StdTail StdTailOf(const TrueSite& site, const Eigen::Vector2d& mark) {
  constexpr double kTailStds = 10.0;
  const ProcessResult& r = site.result;
  const DemEvaluation& all = site.evaluation;
  Raster rest = r.dem;
  StdTail tail;
  double squares = 0.0;
  for (int row = 0; row < rest.rows; ++row)
    for (int col = 0; col < rest.cols; ++col) {
      const float s = r.dem_std.at(row, col);
      if (Raster::IsNoData(rest.at(row, col)) || Raster::IsNoData(s) || s <= 0.0f) continue;
      const double truth = site.truth.Interpolate(rest.CellCentreX(col), rest.CellCentreY(row));
      const double ratio = (rest.at(row, col) - truth) / s;
      if (!(std::abs(ratio) > kTailStds)) continue;
      ++tail.cells, squares += ratio * ratio;
      rest.at(row, col) = Raster::kNoData;
    }
  const double all_squares = all.cells_compared * all.std_ratio_rms * all.std_ratio_rms;
  if (all_squares > 0.0) tail.share_of_squares = squares / all_squares;
  tail.rest = EvaluateDem(rest, site.truth, mark, &r.dem_std);
  return tail;
}

// Issue 22's landforms, each seed: what the DEM and its std claim where the ground hides
// itself from the tripod, against the truth (the true calibration, as the scenes above).
void Landform(const char* scene, double max_rmse_m, uint64_t seed, bench::Table* table) {
  testing::TempDir dir;
  const TrueSite site = ProcessTrueSite(scene, seed, dir);
  const auto& [station, r, truth, e] = site;
  const Eigen::Vector3d mark3 = station->rig.truth.stage.StationMarkInL();
  const StationManifest manifest = LoadStationManifest(dir / "station").value();
  std::map<int, Eigen::Vector3d> camera;
  for (const PairRecord& p : manifest.pairs)
    camera[p.index] =
        station->rig.truth.LFromCamera(Side::kLeft, p.readback.pan_deg, p.readback.tilt_deg)
            .translation();
  // The lines against the ground the simulator rendered, not its 1 m cell means.
  const Raster fine_truth = ReadGeoTiff(dir / "truth/dem_fine.tif").value();
  auto camera_of = [&](const CloudPoint& p) { return camera.at(p.pair); };
  const bench::SightLineViolations v =
      bench::CheckSightLines(r.dem, fine_truth, r.cloud, camera_of, bench::SightLineEnd::kMatched);
  const bench::SightLineViolations true_lines =
      bench::CheckSightLines(r.dem, fine_truth, r.cloud, camera_of, bench::SightLineEnd::kTrue);
  const double tc_true =
      ComputeTerrainCorrection(truth.ResampledOnto(r.dem), nullptr, mark3, {}).total_mgal;
  const double tc_ratio =
      std::abs(r.terrain_correction.total_mgal - tc_true) / r.terrain_correction.sigma_mgal;
  const std::string s = std::string(scene) + " s" + std::to_string(seed) + ": ";
  char target[32];
  std::snprintf(target, sizeof target, "<= %.2f", max_rmse_m);
  // Issue 22 sets its targets on the near region (within 30 m); the square's is beside it.
  table->Add({s + "DEM RMSE within 30 m", e.rmse_30m_m, "m", target, e.rmse_30m_m <= max_rmse_m});
  table->Add({s + "  DEM RMSE, the 60 m square", e.rmse_m, "m", ""});
  table->Add({s + "coverage within 30 m", e.coverage_30m, "", ""});
  table->Add({s + "DEM RMS of error / std", e.std_ratio_rms, "", "0.7-1.5",
              e.std_ratio_rms >= 0.7 && e.std_ratio_rms <= 1.5});
  table->Add({s + "DEM cells within 2 std", e.within_2std, "", ">= 0.90", e.within_2std >= 0.9});
  const Raster ceiling = ReadGeoTiff(dir / "station/products/dem_ceiling.tif").value();
  for (const CellKindHonesty& k : HonestyByCellKind(site, ceiling, mark3.head<2>())) {
    if (k.evaluation.cells_compared == 0) continue;
    table->Add({s + "  RMS of error / std, " + k.name, k.evaluation.std_ratio_rms, "", ""});
    table->Add(
        {s + "  " + k.name + ": share of the sum of (error / std)^2", k.share_of_squares, "", ""});
  }
  const StdTail tail = StdTailOf(site, mark3.head<2>());
  table->Add({s + "  cells more than 10 std off", static_cast<double>(tail.cells), "", ""});
  table->Add({s + "  their share of the sum of (error / std)^2", tail.share_of_squares, "", ""});
  table->Add({s + "  RMS of error / std without them", tail.rest.std_ratio_rms, "", ""});
  table->Add({s + "cells above a line of sight by > 0.1 m", static_cast<double>(v.above), "", "0",
              v.above == 0});
  table->Add({s + "  the most above a line of sight", v.max_above_m, "m", ""});
  table->Add({s + "  cells above a true line of sight by > 0.1 m",
              static_cast<double>(true_lines.above), "", ""});
  table->Add({s + "  the most above a true line of sight", true_lines.max_above_m, "m", ""});
  table->Add({s + "terrain correction error / sigma", tc_ratio, "", "<= 2.0", tc_ratio <= 2.0});
}

}  // namespace

int main(int argc, char** argv) {
  ts::RetainFreedMemory();  // as the appliance does (processing/common/memory.h)
  bench::Table table("points to DEM: simulated surveys and the ISPRS filter test");
  IsprsSamples(&table);
  for (const SceneTargets& t :
       {SceneTargets{"flat", 0.10, 0.01, Bowl(9.5, 6.5, 7.0, 0.5)},
        SceneTargets{"hills", 0.20, 0.01, Bowl(-11.5, 6.5, 5.0, 0.5)},
        SceneTargets{"slope", 0.35, 0.03}, SceneTargets{"forest", 0.35, 0.03}})
    SimulatedSurvey(t, &table);
  std::vector<uint64_t> seeds = bench::SeedsArgument(argc, argv);
  for (const uint64_t seed : seeds)
    for (const char* scene : {"hills", "forest"}) OtherSite(scene, seed, &table);
  if (seeds.empty()) seeds.push_back(1);
  for (const uint64_t seed : seeds)
    for (const auto& [scene, max_rmse_m] :
         std::vector<std::pair<const char*, double>>{{"embankment", 0.25},
                                                     {"terraces", 0.25},
                                                     {"foot", 0.5},
                                                     {"ridge", 0.5},
                                                     {"badlands", 0.5}})
      Landform(scene, max_rmse_m, seed, &table);
  return table.Finish(argc, argv);
}
