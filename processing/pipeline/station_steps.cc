#include "processing/pipeline/station_steps.h"

#include <cmath>
#include <string>
#include <utility>

#include "processing/cloud/ground_filter.h"
#include "processing/cloud/height_blunder_filter.h"
#include "processing/cloud/sight_line_objects.h"
#include "processing/cloud/underside_patches.h"
#include "processing/dem/dem_evaluation.h"
#include "processing/dem/ground_room.h"
#include "processing/dem/horizon_limit.h"

namespace ts {

namespace {

// The line of sight from the left camera of a cloud point's pair to it, in L.
SightLine SightLineOf(const StationWork& w, size_t i) {
  const CloudPoint& p = w.cloud[i];
  SightLine line{w.viewpoints.at(p.pair), p.position_m, 0.0};
  const Eigen::Vector3d ray = (line.point - line.camera).normalized();
  line.range_sigma_m = std::sqrt(std::max(0.0, ray.dot(p.covariance_m2.cast<double>() * ray)));
  return line;
}

template <class T>
void KeepWhere(const std::vector<uint8_t>& keep, std::vector<T>* v) {
  size_t n = 0;
  for (size_t k = 0; k < v->size(); ++k)
    if (keep[k]) (*v)[n++] = std::move((*v)[k]);
  v->resize(n);
}

}  // namespace

bool FilterHeightBlunders(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  // Every point: a line of sight to a point beyond the neighbourhood passes over the square too.
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(w->cloud.size());
  for (const CloudPoint& p : w->cloud) positions.push_back(p.position_m);
  w->blunder = FindHeightBlunders(positions, o.blunders);
  // Only the neighbourhood of the DEM square is made into ground from here on.
  const double reach = o.dem_half_size_m + o.cloud_margin_m;
  w->point_class.assign(w->cloud.size(), kOutsideDem);
  size_t blunders = 0;
  for (size_t i = 0; i < w->cloud.size(); ++i) {
    const Eigen::Vector3d& p = positions[i];
    if (std::abs(p.x()) > reach || std::abs(p.y()) > reach) continue;
    w->region.push_back(p), w->region_index.push_back(static_cast<int>(i));
    w->point_class[i] = w->blunder[i] ? kBlunder : kObject;
    blunders += w->blunder[i];
  }
  s->counts = {{"points", w->cloud.size()},
               {"points_near_square", w->region.size()},
               {"blunders", blunders}};
  if (w->cloud.empty()) {
    s->message =
        "no pair gave a single match: the images hold nothing the matcher can use "
        "(blank, saturated, dark or noise?)";
    return false;
  }
  if (w->region.empty()) {
    s->message = "none of the " + std::to_string(w->cloud.size()) + " points lies within " +
                 OptionNumberText(reach) + " m of the station";
    return false;
  }
  return true;
}

bool FindObjectsAlongSightLines(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  const Calibration& calibration = w->inputs->calibration;
  for (const StereoPairImages& p : w->pairs)
    w->viewpoints[p.index] =
        calibration.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg).translation();
  for (const auto& [pair, centre] : w->viewpoints)
    w->station_viewpoint += centre / w->viewpoints.size();
  const SightLineObjects seen = FindSightLineObjects(w->cloud, w->viewpoints, o.sight_lines);
  for (size_t i = 0; i < w->region.size(); ++i) {
    const int index = w->region_index[i];
    if (w->blunder[index]) continue;
    if (seen.floating[index] || seen.on_face[index])
      w->seen_objects.push_back(w->region[i]);
    else
      w->kept.push_back(w->region[i]), w->kept_index.push_back(index);
  }
  s->counts = {{"floating", seen.floating_count}, {"on_faces", seen.face_count}};
  return true;
}

bool FilterGroundPoints(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  w->ground_of_kept = FilterGround(w->kept, o.ground, w->seen_objects).ground;
  size_t ground = 0;
  for (uint8_t g : w->ground_of_kept) ground += g;
  s->counts = {{"ground_candidates", w->kept.size()}, {"ground_before_patches", ground}};
  return true;
}

bool RemoveUndersidePatches(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  const UndersidePatches underside =
      FindUndersidePatches(w->kept, w->ground_of_kept, w->station_viewpoint, o.underside_patches);
  for (size_t i = 0; i < w->kept.size(); ++i) {
    const bool is_ground = w->ground_of_kept[i] && !underside.underside[i];
    w->point_class[w->kept_index[i]] = is_ground ? kGround : kObject;
    if (!is_ground) continue;
    w->ground.positions.push_back(w->kept[i]);
    const CloudPoint& point = w->cloud[w->kept_index[i]];
    w->ground.height_variances_m2.push_back(point.covariance_m2(2, 2));
    w->ground.matches.push_back({point.pair, point.window});
    w->ground_index.push_back(w->kept_index[i]);
  }
  s->counts = {{"underside_patches", underside.underside_patches},
               {"patches_among_objects", underside.among_objects},
               {"ground", w->ground.positions.size()}};
  if (w->ground.positions.empty()) {
    s->message = "no ground point left to make a DEM of";
    return false;
  }
  return true;
}

bool RemovePointsSeenThroughGround(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  std::vector<SightLine> lines;
  std::vector<size_t> point_of_line;
  for (size_t i = 0; i < w->cloud.size(); ++i)
    if (!w->blunder[i]) lines.push_back(SightLineOf(*w, i)), point_of_line.push_back(i);
  const std::vector<uint8_t> through = FindLinesThroughSeenGround(
      lines, w->ground.positions, w->ground.height_variances_m2, o.dem_cell_m, o.free_space);
  size_t count = 0;
  for (size_t k = 0; k < lines.size(); ++k) {
    if (!through[k]) continue;
    const size_t i = point_of_line[k];
    w->blunder[i] = 1, ++count;
    if (w->point_class[i] != kOutsideDem) w->point_class[i] = kBlunder;
  }
  std::vector<uint8_t> keep(w->ground_index.size());
  for (size_t j = 0; j < keep.size(); ++j) keep[j] = !w->blunder[w->ground_index[j]];
  KeepWhere(keep, &w->ground.positions), KeepWhere(keep, &w->ground.height_variances_m2);
  KeepWhere(keep, &w->ground.matches), KeepWhere(keep, &w->ground_index);
  keep.assign(w->kept_index.size(), 0);
  for (size_t j = 0; j < keep.size(); ++j) keep[j] = !w->blunder[w->kept_index[j]];
  KeepWhere(keep, &w->kept), KeepWhere(keep, &w->kept_index), KeepWhere(keep, &w->ground_of_kept);
  s->counts = {{"seen_through_ground", count}};
  if (w->ground.positions.empty()) {
    s->message = "no ground point left to make a DEM of";
    return false;
  }
  return true;
}

// The ground points and the station mark, a ground point surveyed exactly (the tripod hides
// the ground around it from the cameras; the terrain correction ties the surface to it).
KrigingPoints GroundAndMark(const StationWork& w) {
  KrigingPoints known = w.ground;
  known.surveyed.push_back(w.mark_dem);
  return known;
}

bool KrigeStationDem(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  const StationInputs& in = *w->inputs;
  const Eigen::Vector3d mark_l = in.calibration.stage.StationMarkInL();
  w->station_xy = mark_l.head<2>();
  std::string crs_wkt;
  if (in.georeference) {
    for (Eigen::Vector3d& p : w->ground.positions) p = in.georeference->ToWorld(p);
    w->station_xy = in.georeference->ToWorld(mark_l).head<2>();
    crs_wkt = in.georeference->crs_wkt;
  }
  w->mark_dem = {w->station_xy.x(), w->station_xy.y(),
                 in.georeference ? in.georeference->ToWorld(mark_l).z() : mark_l.z()};
  // A square of whole cells around the station (snapped to the cell grid in a CRS).
  const int cells = static_cast<int>(std::lround(2 * o.dem_half_size_m / o.dem_cell_m));
  double min_x = w->station_xy.x() - o.dem_half_size_m;
  double max_y = w->station_xy.y() + o.dem_half_size_m;
  if (in.georeference) {
    min_x = std::floor(min_x / o.dem_cell_m) * o.dem_cell_m;
    max_y = std::ceil(max_y / o.dem_cell_m) * o.dem_cell_m;
  }
  Raster grid = Raster::Make(min_x, max_y, o.dem_cell_m, cells, cells);
  grid.crs_wkt = crs_wkt;
  // Kriging reaches as far as object shadows may; LimitDemToHorizon takes back what no object
  // hid. The mark is kriged with the ground: under the tripod, where no camera looks, it is
  // the one height known.
  KrigingOptions kriging = o.kriging;
  kriging.max_distance_m = o.horizon.KrigingReach(o.kriging.max_distance_m);
  w->kriged = KrigeDem(GroundAndMark(*w), grid, kriging);
  w->kriged.dem.crs_wkt = w->kriged.std.crs_wkt = crs_wkt;
  s->counts = {{"kriging_points", w->kriged.points_used}, {"cells", cells * cells}};
  return true;
}

bool LimitDemToHorizon(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  const StationInputs& in = *w->inputs;
  // Extrapolated past a brow, no higher than the horizon; beyond kriging's reach only in an
  // object's shadow (every point seen, ground or not).
  std::vector<Eigen::Vector3d> seen_points = w->kept;
  std::vector<uint8_t> seen_ground(w->kept.size(), 0);
  for (size_t i = 0; i < w->kept.size(); ++i)
    seen_ground[i] = w->point_class[w->kept_index[i]] == kGround;
  seen_points.insert(seen_points.end(), w->seen_objects.begin(), w->seen_objects.end());
  seen_ground.resize(seen_points.size(), 0);
  Eigen::Vector3d viewpoint = w->station_viewpoint;
  if (in.georeference) {
    for (Eigen::Vector3d& p : seen_points) p = in.georeference->ToWorld(p);
    viewpoint = in.georeference->ToWorld(viewpoint);
  }
  HorizonLimitResult horizon =
      LimitToHorizon(seen_points, seen_ground, viewpoint, o.horizon, &w->kriged.dem, &w->kriged.std,
                     o.kriging.max_distance_m);
  w->horizon = std::move(horizon.horizon);
  w->coverage_30m = DemCoverage(w->kriged.dem, w->station_xy, 30.0);
  w->coverage_square = DemCoverage(w->kriged.dem, w->station_xy, 0.0);
  if (w->coverage_30m < 0.95)
    s->warnings.push_back("DEM covers only " +
                          std::to_string(static_cast<int>(100 * w->coverage_30m)) +
                          " % of the cells within 30 m of the station");
  s->counts = {{"cells_lowered_to_horizon", horizon.cells_lowered},
               {"cells_in_object_shadows", horizon.cells_in_object_shadows}};
  return true;
}

bool KeepBelowSightLines(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  const StationInputs& in = *w->inputs;
  // Every point but the height blunders, from the left camera of its pair: ground and objects
  // (a line to a tree's crown passes over ground too), points the sight-line tests took for
  // objects (a trunk is solid; a point matched in front of the surface stops its line short
  // of the ground), and points beyond the neighbourhood (the line to a lower terrace 50 m
  // out passes over the riser before it). Only a point matched behind the surface would cut
  // into it, by more than its range sigma; its line passes under ground other points saw, and
  // RemovePointsSeenThroughGround has taken it out with its point.
  std::vector<SightLine> lines;
  lines.reserve(w->cloud.size());
  for (size_t i = 0; i < w->cloud.size(); ++i) {
    if (w->blunder[i]) continue;
    SightLine line = SightLineOf(*w, i);
    if (in.georeference) {
      line.camera = in.georeference->ToWorld(line.camera);
      line.point = in.georeference->ToWorld(line.point);
    }
    lines.push_back(line);
  }
  w->ceilings = FindSightLineCeilings(lines, w->kriged.dem, o.free_space);
  const FreeSpaceResult lowered =
      LowerBelowSightLines(w->ceilings, o.free_space, &w->kriged.dem, &w->kriged.std);
  s->counts = {{"sight_lines", lines.size()},
               {"ceilings", w->ceilings.ceilings.size()},
               {"cells_lowered", lowered.cells_lowered},
               {"mean_lowering_m", lowered.mean_lowering_m},
               {"max_lowering_m", lowered.max_lowering_m}};
  return true;
}

bool AddGroundRoom(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  const GroundRoomResult room = WidenStdByGroundRoom(GroundAndMark(*w), w->kriged.dem, &w->ceilings,
                                                     o.ground_room, &w->kriged.std);
  s->counts = {{"seen_cells", room.seen_cells},
               {"unseen_cells", room.unseen_cells},
               {"median_unseen_room_m", room.median_unseen_widening_m},
               {"median_seen_departure_m", room.median_seen_departure_m}};
  return true;
}

bool AddSightTiltSigma(const ProcessOptions&, StationWork* w, StepSummary* s) {
  const double sigma_rad = w->sight_tilt_sigma_deg * M_PI / 180.0;
  s->counts = {{"sight_tilt_sigma_deg", w->sight_tilt_sigma_deg}};
  if (sigma_rad <= 0.0) return true;
  Raster& std_dev = w->kriged.std;
  for (int row = 0; row < std_dev.rows; ++row)
    for (int col = 0; col < std_dev.cols; ++col) {
      float& v = std_dev.at(row, col);
      if (Raster::IsNoData(v)) continue;
      const double r = std::hypot(std_dev.CellCentreX(col) - w->station_xy.x(),
                                  std_dev.CellCentreY(row) - w->station_xy.y());
      v = static_cast<float>(std::hypot(v, sigma_rad * r));
    }
  return true;
}

bool CorrectTerrain(const ProcessOptions& o, StationWork* w, StepSummary* s) {
  // Every cell of the square: where the DEM has no value, the ground's best estimate and room.
  const GroundEstimate every_cell =
      EstimateEveryCell(GroundAndMark(*w), w->kriged.dem, w->kriged.std, &w->ceilings,
                        w->horizon.values.empty() ? nullptr : &w->horizon, o.ground_room);
  w->terrain_correction = ComputeTerrainCorrection(every_cell.height, &every_cell.std, w->mark_dem,
                                                   o.terrain_correction, &every_cell.kind);
  for (const std::string& warning : w->terrain_correction.warnings)
    s->warnings.push_back("terrain correction: " + warning);
  return true;
}

}  // namespace ts
