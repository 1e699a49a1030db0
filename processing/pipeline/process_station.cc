#include "processing/pipeline/process_station.h"

#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "processing/dem/dem_evaluation.h"
#include "processing/dem/georeference.h"
#include "processing/geometry/theoretical_accuracy.h"
#include "processing/gravity/terrain_correction_json.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/image_file.h"
#include "processing/io/point_cloud_file.h"
#include "processing/io/raster.h"
#include "processing/io/station_validator.h"
#include "processing/matching/station_matching.h"
#include "processing/products/dem_image.h"

namespace ts {

bool ProcessOptions::Check(std::string* why) const {
  std::string err;
  if (!(dem_half_size_m > 0.0) || !(dem_cell_m > 0.0) || !(cloud_margin_m >= 0.0))
    err = "DEM size, cell and margin must be positive";
  else if (!matching.Check(&err))
    err = "matching: " + err;
  else if (!blunders.Check(&err))
    err = "blunder filter: " + err;
  else if (!sight_lines.Check(&err))
    err = "sight-line objects: " + err;
  else if (!ground.Check(&err))
    err = "ground filter: " + err;
  else if (!underside_patches.Check(&err))
    err = "underside patches: " + err;
  else if (!kriging.Check(&err))
    err = "kriging: " + err;
  else if (!horizon.Check(&err))
    err = "horizon: " + err;
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

using Clock = std::chrono::steady_clock;

class StageTimer {
 public:
  explicit StageTimer(const ProcessOptions& o) : options_(o) {}
  void Start(const std::string& stage) {
    Stop();
    stage_ = stage;
    start_ = Clock::now();
    if (options_.progress) options_.progress(stage);
  }
  void Stop() {
    if (stage_.empty()) return;
    timings_[stage_] = std::chrono::duration<double>(Clock::now() - start_).count();
    stage_.clear();
  }
  const nlohmann::json& timings() const { return timings_; }

 private:
  const ProcessOptions& options_;
  std::string stage_;
  Clock::time_point start_;
  nlohmann::json timings_ = nlohmann::json::object();
};

Result<std::vector<StereoPairImages>> LoadPairs(const std::string& dir, const StationManifest& m) {
  std::vector<StereoPairImages> pairs(m.pairs.size());
  std::vector<std::string> errors(m.pairs.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(m.pairs.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const PairRecord& p = m.pairs[i];
      auto left =
          ReadMonoPng(dir + "/" + p.left.file, m.pixel_format, m.image_width_px, m.image_height_px);
      auto right = ReadMonoPng(dir + "/" + p.right.file, m.pixel_format, m.image_width_px,
                               m.image_height_px);
      if (!left || !right) {
        errors[i] = !left ? left.error() : right.error();
        continue;
      }
      pairs[i] = {p.index, p.readback.pan_deg, p.readback.tilt_deg, *left, *right};
    }
  });
  for (const std::string& e : errors)
    if (!e.empty()) return Error{e};
  std::sort(pairs.begin(), pairs.end(),
            [](const StereoPairImages& a, const StereoPairImages& b) { return a.index < b.index; });
  return pairs;
}

double PeakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kB on Linux
}

}  // namespace

Result<ProcessResult> ProcessStation(const std::string& dir, const ProcessOptions& o) {
  std::string why;
  if (!o.Check(&why)) return Error{"process options: " + why};
  const auto wall_start = Clock::now();
  StageTimer timer(o);
  nlohmann::json warnings = nlohmann::json::array();

  timer.Start("load");
  StationValidationOptions validation;
  validation.decode_images = false;  // LoadPairs decodes and checks each image once
  Result<StationManifest> manifest = ValidateStation(dir, validation);
  if (!manifest) return Error{manifest.error()};
  if (manifest->pairs.empty()) return Error{dir + "/station.json: pairs: no pair captured"};
  if (!manifest->Complete())
    warnings.push_back("station incomplete: " + std::to_string(manifest->pairs.size()) + " of " +
                       std::to_string(manifest->plan.size()) + " pairs");
  Calibration calibration = manifest->calibration;
  if (!o.calibration_file.empty()) {
    Result<Calibration> c = LoadCalibrationYaml(o.calibration_file);
    if (!c) return Error{c.error()};
    calibration = *c;
  }
  std::optional<Georeference> georeference;
  if (!o.gcp_file.empty()) {
    Result<Georeference> g = LoadGeoreference(o.gcp_file);
    if (!g) return Error{g.error()};
    georeference = *g;
  }
  Result<std::vector<StereoPairImages>> pairs = LoadPairs(dir, *manifest);
  if (!pairs) return Error{pairs.error()};

  timer.Start("matching");
  StationMatchResult matched = MatchStation(calibration, *pairs, o.matching);
  const PointCloud& cloud = matched.cloud;

  timer.Start("blunder_filter");
  // Only the neighbourhood of the DEM square matters from here on.
  const double reach = o.dem_half_size_m + o.cloud_margin_m;
  std::vector<Eigen::Vector3d> region;
  std::vector<int> region_index;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d& p = cloud[i].position_m;
    if (std::abs(p.x()) <= reach && std::abs(p.y()) <= reach)
      region.push_back(p), region_index.push_back(static_cast<int>(i));
  }
  const std::vector<uint8_t> blunder = FindHeightBlunders(region, o.blunders);

  timer.Start("ground_filter");
  std::map<int, Eigen::Vector3d> viewpoints;
  for (const StereoPairImages& p : *pairs)
    viewpoints[p.index] = calibration.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg).translation();
  const SightLineObjects seen = FindSightLineObjects(cloud, viewpoints, o.sight_lines);
  std::vector<Eigen::Vector3d> kept, seen_objects;
  std::vector<int> kept_index;
  std::vector<uint8_t> class_of(cloud.size(), kOutsideDem);
  for (size_t i = 0; i < region.size(); ++i) {
    const int index = region_index[i];
    class_of[index] = blunder[i] ? kBlunder : kObject;
    if (blunder[i]) continue;
    if (seen.floating[index] || seen.on_face[index])
      seen_objects.push_back(region[i]);
    else
      kept.push_back(region[i]), kept_index.push_back(index);
  }
  const GroundFilterResult ground = FilterGround(kept, o.ground, seen_objects);
  Eigen::Vector3d station_viewpoint = Eigen::Vector3d::Zero();  // the cameras' mean centre
  for (const auto& [pair, centre] : viewpoints) station_viewpoint += centre / viewpoints.size();
  const UndersidePatches underside =
      FindUndersidePatches(kept, ground.ground, station_viewpoint, o.underside_patches);
  KrigingPoints ground_points;
  for (size_t i = 0; i < kept.size(); ++i) {
    const bool is_ground = ground.ground[i] && !underside.underside[i];
    class_of[kept_index[i]] = is_ground ? kGround : kObject;
    if (!is_ground) continue;
    ground_points.positions.push_back(kept[i]);
    ground_points.height_variances_m2.push_back(cloud[kept_index[i]].covariance_m2(2, 2));
  }

  timer.Start("kriging");
  const Eigen::Vector3d mark_l = calibration.stage.StationMarkInL();
  Eigen::Vector2d station_xy = mark_l.head<2>();
  std::string crs_wkt;
  if (georeference) {
    for (Eigen::Vector3d& p : ground_points.positions) p = georeference->ToWorld(p);
    station_xy = georeference->ToWorld(mark_l).head<2>();
    crs_wkt = georeference->crs_wkt;
  }
  // A square of whole cells around the station (snapped to the cell grid in a CRS).
  const int cells = static_cast<int>(std::lround(2 * o.dem_half_size_m / o.dem_cell_m));
  double min_x = station_xy.x() - o.dem_half_size_m, max_y = station_xy.y() + o.dem_half_size_m;
  if (georeference) {
    min_x = std::floor(min_x / o.dem_cell_m) * o.dem_cell_m;
    max_y = std::ceil(max_y / o.dem_cell_m) * o.dem_cell_m;
  }
  Raster grid = Raster::Make(min_x, max_y, o.dem_cell_m, cells, cells);
  grid.crs_wkt = crs_wkt;
  // Kriging reaches as far as object shadows may; LimitToHorizon takes back what no object hid.
  KrigingOptions kriging = o.kriging;
  kriging.max_distance_m = o.horizon.KrigingReach(o.kriging.max_distance_m);
  KrigingResult kriged = KrigeDem(ground_points, grid, kriging);
  kriged.dem.crs_wkt = kriged.std.crs_wkt = crs_wkt;
  // Extrapolated past a brow, no higher than the horizon; beyond kriging's reach only in an
  // object's shadow (every point seen, ground or not).
  std::vector<Eigen::Vector3d> seen_points = kept;
  std::vector<uint8_t> seen_ground(kept.size(), 0);
  for (size_t i = 0; i < kept.size(); ++i) seen_ground[i] = class_of[kept_index[i]] == kGround;
  seen_points.insert(seen_points.end(), seen_objects.begin(), seen_objects.end());
  seen_ground.resize(seen_points.size(), 0);
  Eigen::Vector3d viewpoint = station_viewpoint;
  if (georeference) {
    for (Eigen::Vector3d& p : seen_points) p = georeference->ToWorld(p);
    viewpoint = georeference->ToWorld(viewpoint);
  }
  const HorizonLimitResult horizon =
      LimitToHorizon(seen_points, seen_ground, viewpoint, o.horizon, &kriged.dem, &kriged.std,
                     o.kriging.max_distance_m);
  const double coverage_30m = DemCoverage(kriged.dem, station_xy, 30.0);
  const double coverage_square = DemCoverage(kriged.dem, station_xy, 0.0);
  if (coverage_30m < 0.95)
    warnings.push_back("DEM covers only " + std::to_string(static_cast<int>(100 * coverage_30m)) +
                       " % of the cells within 30 m of the station");

  timer.Start("terrain_correction");
  const Eigen::Vector3d mark_dem(station_xy.x(), station_xy.y(),
                                 georeference ? georeference->ToWorld(mark_l).z() : mark_l.z());
  const TerrainCorrection tc =
      ComputeTerrainCorrection(kriged.dem, &kriged.std, mark_dem, o.terrain_correction);
  for (const std::string& w : tc.warnings) warnings.push_back("terrain correction: " + w);

  timer.Start("products");
  const std::string products = dir + "/products";
  std::error_code ec;
  std::filesystem::create_directories(products, ec);
  if (ec) return Error{products + ": cannot create (" + ec.message() + ")"};
  {
    std::vector<Eigen::Vector3d> xyz(cloud.size());
    PlyColumn sigma{"sigma", {}, {}, {}}, sigma_z{"sigma_z", {}, {}, {}};
    PlyColumn pair{"pair", {}, {}, {}}, correlation{"correlation", {}, {}, {}};
    PlyColumn ground_flag{"ground", {}, {}, {}}, classification{"class", {}, {}, {}};
    for (size_t i = 0; i < cloud.size(); ++i) {
      xyz[i] = georeference ? georeference->ToWorld(cloud[i].position_m) : cloud[i].position_m;
      sigma.f32.push_back(std::sqrt(cloud[i].covariance_m2.trace()));
      sigma_z.f32.push_back(std::sqrt(cloud[i].covariance_m2(2, 2)));
      pair.i32.push_back(cloud[i].pair);
      correlation.f32.push_back(cloud[i].correlation);
      ground_flag.u8.push_back(class_of[i] == kGround);
      classification.u8.push_back(class_of[i]);
    }
    Status s = WritePly(products + "/points.ply", xyz,
                        {sigma, sigma_z, pair, correlation, ground_flag, classification});
    if (!s) return Error{s.error()};
  }
  for (const auto& [raster, name] :
       {std::pair{&kriged.dem, "dem.tif"}, std::pair{&kriged.std, "dem_std.tif"}}) {
    Status s = WriteGeoTiff(*raster, products + "/" + name);
    if (!s) return Error{s.error()};
  }
  if (Status s = WriteFileAtomically(
          products + "/terrain_correction.json",
          TerrainCorrectionToJson(tc, o.terrain_correction, mark_dem).dump(2) + "\n");
      !s)
    return Error{s.error()};
  if (auto s = WritePngAtomically(RenderDemImage(kriged.dem, station_xy), products + "/dem.png");
      !s)
    return Error{s.error()};
  if (auto s = WritePngAtomically(RenderPanorama(calibration, *pairs, o.panorama),
                                  products + "/panorama.png");
      !s)
    return Error{s.error()};
  timer.Stop();

  // The report, last: its presence says the products are complete.
  nlohmann::json report;
  report["station"] = manifest->station_id;
  report["frame"] = georeference ? "projected CRS (GCPs)" : "station frame L";
  report["station_mark"] = {mark_dem.x(), mark_dem.y(), mark_dem.z()};
  report["terrain_correction_mgal"] = tc.total_mgal;
  report["terrain_correction_sigma_mgal"] = tc.sigma_mgal;
  report["timings_s"] = timer.timings();
  report["timings_s"]["rectification_maps"] = matched.rectification_s;
  report["wall_s"] = std::chrono::duration<double>(Clock::now() - wall_start).count();
  report["peak_memory_mib"] = PeakMemoryMiB();
  size_t blunders = 0, objects = 0;
  for (uint8_t c : class_of) blunders += c == kBlunder, objects += c == kObject;
  report["counts"] = {{"pairs", pairs->size()},
                      {"points", cloud.size()},
                      {"points_near_square", region.size()},
                      {"blunders", blunders},
                      {"objects", objects},
                      {"floating", seen.floating_count},
                      {"on_faces", seen.face_count},
                      {"underside_patches", underside.underside_patches},
                      {"patches_among_objects", underside.among_objects},
                      {"cells_lowered_to_horizon", horizon.cells_lowered},
                      {"cells_in_object_shadows", horizon.cells_in_object_shadows},
                      {"ground", ground_points.positions.size()},
                      {"kriging_points", kriged.points_used}};
  nlohmann::json per_pair = nlohmann::json::array();
  for (size_t i = 0; i < matched.pairs.size(); ++i) {
    const PairMatchSummary& s = matched.pairs[i];
    per_pair.push_back({{"pair", (*pairs)[i].index},
                        {"interest_points", s.points},
                        {"matched", s.consistent},
                        {"matching_s", s.matching_s}});
    if (s.consistent < 1000)
      warnings.push_back("pair " + std::to_string((*pairs)[i].index) + " gave only " +
                         std::to_string(s.consistent) + " matches");
  }
  report["pairs"] = per_pair;
  report["variogram"] = {{"model", VariogramKindName(kriged.model.kind)},
                         {"nugget_m2", kriged.model.nugget},
                         {"partial_sill_m2", kriged.model.partial_sill},
                         {"range_m", kriged.model.range_m}};
  report["dem"] = {{"cell_m", o.dem_cell_m},
                   {"cells", cells * cells},
                   {"coverage_30m", coverage_30m},
                   {"coverage_square", coverage_square}};
  if (georeference) {
    report["georeference"] = {{"scale", georeference->scale},
                              {"rotation_deg", georeference->rotation_rad * 180.0 / M_PI},
                              {"height_offset_m", georeference->height_offset_m},
                              {"gcp_residuals_m", georeference->residuals_m}};
  }
  nlohmann::json accuracy = nlohmann::json::array();
  for (const AccuracyRow& row :
       TheoreticalAccuracy(calibration.rig.baseline_m, calibration.rig.left.principal_distance_px,
                           TheoreticalAccuracyOptions{}))
    accuracy.push_back({{"range_m", row.range_m},
                        {"sigma_x_m", row.sigma_x_m},
                        {"sigma_y_m", row.sigma_y_m},
                        {"sigma_z_m", row.sigma_z_m}});
  report["theoretical_accuracy"] = accuracy;
  report["warnings"] = warnings;
  if (Status s = WriteFileAtomically(products + "/report.json", report.dump(2) + "\n"); !s)
    return Error{s.error()};
  ProcessResult result;
  result.report = std::move(report);
  result.cloud = std::move(matched.cloud);
  result.point_class = std::move(class_of);
  result.dem = std::move(kriged.dem);
  result.dem_std = std::move(kriged.std);
  result.terrain_correction = tc;
  return result;
}

}  // namespace ts
