#include "processing/change/change_json.h"

#include <ogr_spatialref.h>

namespace ts {
namespace {

nlohmann::json ToJson(const ChangeVolume& v) {
  return {{"cells", v.cells},
          {"area_m2", v.area_m2},
          {"volume_m3", v.volume_m3},
          {"sigma_m3", v.sigma_m3},
          {"sigma_fully_correlated_m3", v.sigma_correlated_m3}};
}

nlohmann::json Xy(const Eigen::Vector2d& p) { return {p.x(), p.y()}; }

// GeoJSON: a Polygon, or a MultiPolygon where the outline has several.
nlohmann::json Geometry(const SubsidenceRegion& region) {
  auto ring_json = [](const std::vector<Eigen::Vector2d>& ring) {
    nlohmann::json j = nlohmann::json::array();
    for (const Eigen::Vector2d& p : ring) j.push_back(Xy(p));
    return j;
  };
  nlohmann::json polygons = nlohmann::json::array();
  for (const OutlinePolygon& p : region.outline) {
    nlohmann::json polygon = nlohmann::json::array({ring_json(p.exterior)});
    for (const auto& hole : p.holes) polygon.push_back(ring_json(hole));
    polygons.push_back(polygon);
  }
  if (polygons.size() == 1) return {{"type", "Polygon"}, {"coordinates", polygons[0]}};
  return {{"type", "MultiPolygon"}, {"coordinates", polygons}};
}

nlohmann::json RegionProperties(const SubsidenceRegion& r) {
  return {{"id", r.id},
          {"area_m2", r.lowering.area_m2},
          {"significant_cells", r.significant_cells},
          {"volume_m3", r.lowering.volume_m3},
          {"sigma_m3", r.lowering.sigma_m3},
          {"sigma_fully_correlated_m3", r.lowering.sigma_correlated_m3},
          {"max_depth_m", r.max_depth_m},
          {"max_depth_sigma_m", r.max_depth_sigma_m},
          {"deepest_xy", Xy(r.deepest_xy_m)},
          {"centroid_xy", Xy(r.centroid_xy_m)}};
}

std::string CrsLabel(const std::string& wkt) {
  if (wkt.empty()) return "station frame L (x east, y north, m)";
  OGRSpatialReference s;
  if (s.importFromWkt(wkt.c_str()) != OGRERR_NONE || !s.GetName()) return "CRS of the DEMs";
  return s.GetName();
}

}  // namespace

nlohmann::json SubsidenceGeoJson(const ChangeResult& change) {
  nlohmann::json features = nlohmann::json::array();
  for (const SubsidenceRegion& r : change.regions)
    features.push_back(
        {{"type", "Feature"}, {"properties", RegionProperties(r)}, {"geometry", Geometry(r)}});
  nlohmann::json collection = {
      {"type", "FeatureCollection"}, {"name", "subsidence"}, {"features", features}};
  if (!change.dod.crs_wkt.empty()) {
    // GeoJSON 2008 named CRS, which GDAL and QGIS read for projected coordinates.
    OGRSpatialReference s;
    if (s.importFromWkt(change.dod.crs_wkt.c_str()) == OGRERR_NONE && s.GetAuthorityName(nullptr) &&
        s.GetAuthorityCode(nullptr))
      collection["crs"] = {
          {"type", "name"},
          {"properties",
           {{"name", std::string("urn:ogc:def:crs:") + s.GetAuthorityName(nullptr) +
                         "::" + s.GetAuthorityCode(nullptr)}}}};
  }
  return collection;
}

nlohmann::json ChangeToJson(const ChangeResult& c, const ChangeOptions& o) {
  nlohmann::json lod = o.lod_m > 0.0
                           ? nlohmann::json{{"method", "fixed"}, {"lod_m", o.lod_m}}
                           : nlohmann::json{{"method", "t-test: |dz| >= t_critical * sigma"},
                                            {"t_critical", o.t_critical}};
  nlohmann::json max_subsidence = nullptr;
  if (c.max_subsidence_m)
    max_subsidence = {{"depth_m", *c.max_subsidence_m},
                      {"sigma_m", c.max_subsidence_sigma_m},
                      {"xy", Xy(c.max_subsidence_xy_m)}};
  nlohmann::json regions = nlohmann::json::array();
  for (const SubsidenceRegion& r : c.regions) {
    nlohmann::json j = RegionProperties(r);
    j["outline"] = Geometry(r);
    regions.push_back(j);
  }
  return {{"schema", "topostation.change"},
          {"schema_version", 1},
          {"dz", "after - before, m (negative: the ground went down)"},
          {"frame", CrsLabel(c.dod.crs_wkt)},
          {"grid",
           {{"min_x", c.dod.min_x_m},
            {"max_y", c.dod.max_y_m},
            {"cell_m", c.dod.cell_m},
            {"cols", c.dod.cols},
            {"rows", c.dod.rows}}},
          {"after_resampled_onto_before", c.after_resampled},
          {"sigma", c.sigma_from_lod ? "level of detection / t_critical (no std grids)"
                                     : "sqrt(std_before^2 + std_after^2) per cell"},
          {"level_of_detection", lod},
          {"cells_compared", c.cells_compared},
          {"area_compared_m2", c.area_compared_m2},
          {"compared_fraction_before", c.compared_fraction_before},
          {"compared_fraction_after", c.compared_fraction_after},
          {"lowering", ToJson(c.lowering)},
          {"raising", ToJson(c.raising)},
          {"net_volume_m3", c.net_volume_m3},
          {"net_sigma_m3", c.net_sigma_m3},
          {"max_subsidence", max_subsidence},
          {"stable_ground_median_dz_m", c.stable_median_m},
          {"height_offset_removed_m", c.offset_removed_m},
          {"min_region_area_m2", o.min_region_area_m2},
          {"regions",
           "significant cores of at least min_region_area_m2 whose deepest cell reaches "
           "region_deepest_t sigma (t_critical's level over all compared cells at once), grown "
           "into 4-neighbours lowered by at least region_grow_t sigma, then ring by ring (up to "
           "basin_reach_m) while a ring's mean lowering is significant at t_critical; volume: "
           "the net lowering over it"},
          {"region_deepest_t", c.region_deepest_t},
          {"region_grow_t", o.region_grow_t},
          {"basin_reach_m", o.basin_reach_m},
          {"subsidence_regions", regions},
          {"warnings", c.warnings}};
}

}  // namespace ts
