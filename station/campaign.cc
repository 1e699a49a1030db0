#include "station/campaign.h"

#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "processing/io/json_fields.h"
#include "processing/io/raster.h"
#include "processing/io/station_manifest.h"
#include "station/station_verdict.h"

namespace ts {
namespace {

namespace fs = std::filesystem;

nlohmann::json Field(const nlohmann::json& object, const char* key) {
  return object.is_object() && object.contains(key) ? object[key] : nlohmann::json();
}

// The crew's instrument height (the tilt axis above the mark) from the manifest's stage, where
// L's origin lies the tilt axis's height below it (StageKinematics::InstrumentHeightM).
nlohmann::json InstrumentHeight(const nlohmann::json& manifest) {
  const nlohmann::json stage = Field(Field(manifest, "calibration"), "stage");
  const nlohmann::json origin = Field(stage, "height_above_mark_m");
  if (!origin.is_number()) return nullptr;
  const nlohmann::json axis = Field(stage, "tilt_axis_offset_m");
  const bool has_axis = axis.is_array() && axis.size() == 3 && axis[2].is_number();
  // A tape reads to the millimetre: to 0.1 mm, the sum prints as the crew entered it.
  return std::round((origin.get<double>() + (has_axis ? axis[2].get<double>() : 0.0)) * 1e4) / 1e4;
}

std::string RingColumn(const nlohmann::json& ring) {
  auto edge = [](const nlohmann::json& v) {
    if (!v.is_number()) return std::string("end");
    std::ostringstream out;
    out << v.get<double>();
    return out.str();
  };
  return "ring_" + edge(ring["inner_m"]) + "_" + edge(ring["outer_m"]) + "_mgal";
}

std::string CsvCell(const nlohmann::ordered_json& v) {
  std::string text;
  if (v.is_null()) return "";
  if (v.is_string())
    text = v.get<std::string>();
  else if (v.is_array()) {
    for (const auto& item : v) {
      if (!text.empty()) text += " | ";
      text += item.get<std::string>();
    }
  } else {
    text = v.dump();
  }
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// EPSG:4326, longitude first.
OGRSpatialReference Wgs84() {
  OGRSpatialReference wgs84;
  wgs84.importFromEPSG(4326);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return wgs84;
}

// From the DEM's CRS to EPSG:4326 when the DEM is in one (georeferenced with GCPs); nullptr
// for a DEM in the station frame L.
std::unique_ptr<OGRCoordinateTransformation> DemToWgs84(const Raster& dem,
                                                        const OGRSpatialReference& wgs84) {
  if (dem.crs_wkt.empty()) return nullptr;
  OGRSpatialReference crs;
  if (crs.importFromWkt(dem.crs_wkt.c_str()) != OGRERR_NONE) return nullptr;
  crs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return std::unique_ptr<OGRCoordinateTransformation>(
      OGRCreateCoordinateTransformation(&crs, &wgs84));
}

// The station mark of a georeferenced DEM (terrain_correction.json's, in the DEM's CRS) as
// latitude, longitude and height; false when the DEM is in L or the mark unknown.
bool MarkFromGcps(const std::string& dir, const nlohmann::json& tc, nlohmann::ordered_json* row) {
  const nlohmann::json mark = Field(tc, "station_mark");
  if (!mark.is_array() || mark.size() != 3 || !mark[0].is_number()) return false;
  const Result<Raster> dem = ReadGeoTiff(dir + "/products/dem.tif");
  if (!dem) return false;
  const OGRSpatialReference wgs84 = Wgs84();
  const auto to_wgs84 = DemToWgs84(*dem, wgs84);
  double x = mark[0].get<double>(), y = mark[1].get<double>();
  if (!to_wgs84 || !to_wgs84->Transform(1, &x, &y)) return false;
  (*row)["lat_deg"] = y;
  (*row)["lon_deg"] = x;
  (*row)["height_m"] = mark[2];
  (*row)["position_source"] = "GCPs";
  return true;
}

}  // namespace

Result<std::vector<std::string>> FindStations(const std::vector<std::string>& dirs) {
  std::vector<std::string> stations;
  for (const std::string& dir : dirs) {
    if (fs::exists(fs::path(dir) / kManifestFileName)) {
      stations.push_back(dir);
      continue;
    }
    if (!fs::is_directory(dir)) return Error{dir + ": not a station nor a directory of stations"};
    std::vector<std::string> inside;
    for (const auto& e : fs::directory_iterator(dir))
      if (fs::exists(e.path() / kManifestFileName)) inside.push_back(e.path().string());
    if (inside.empty()) return Error{dir + ": no station in it (no */station.json)"};
    std::sort(inside.begin(), inside.end());
    stations.insert(stations.end(), inside.begin(), inside.end());
  }
  return stations;
}

Result<nlohmann::ordered_json> CampaignRow(const std::string& dir) {
  const nlohmann::json manifest = ReadJsonFileOrNull((fs::path(dir) / kManifestFileName).string());
  if (!manifest.is_object()) return Error{dir + "/station.json: not readable JSON"};
  const nlohmann::json fields =
      ReadJsonFileOrNull((fs::path(dir) / "station_fields.json").string());
  const nlohmann::json report =
      ReadJsonFileOrNull((fs::path(dir) / "products/report.json").string());
  const nlohmann::json tc =
      ReadJsonFileOrNull((fs::path(dir) / "products/terrain_correction.json").string());
  const nlohmann::json evaluation =
      ReadJsonFileOrNull((fs::path(dir) / "products/evaluation.json").string());
  const nlohmann::json gnss = Field(fields, "gnss");
  nlohmann::ordered_json row;
  row["station"] = manifest.value("station_id", fs::path(dir).filename().string());
  row["line"] = Field(fields, "line");
  const nlohmann::json pairs = Field(manifest, "pairs");
  row["time_utc"] = pairs.is_array() && !pairs.empty() ? Field(pairs[0], "captured_utc")
                                                       : Field(manifest, "created_utc");
  row["instrument_height_m"] = InstrumentHeight(manifest);
  row["lat_deg"] = Field(gnss, "lat_deg");
  row["lon_deg"] = Field(gnss, "lon_deg");
  row["height_m"] = Field(gnss, "height_m");
  row["position_source"] = gnss.is_object() ? nlohmann::json("GNSS") : nlohmann::json();
  if (!gnss.is_object()) MarkFromGcps(dir, tc, &row);
  row["density_g_cm3"] = Field(tc, "density_g_cm3");
  row["terrain_correction_mgal"] = Field(report, "terrain_correction_mgal");
  row["terrain_correction_sigma_mgal"] = Field(report, "terrain_correction_sigma_mgal");
  for (const nlohmann::json& ring :
       Field(tc, "rings").is_array() ? tc["rings"] : nlohmann::json::array())
    row[RingColumn(ring)] = Field(ring, "mgal");
  row["coverage_30m"] = Field(Field(report, "dem"), "coverage_30m");
  row["dem_rmse_m"] = Field(evaluation, "dem_rmse_m");
  row["calibration"] = Field(Field(report, "calibration"), "source");
  const StationVerdict verdict = JudgeStationDir(dir);
  row["verdict"] = verdict.verdict;
  row["verdict_reason"] = verdict.text;
  row["warnings"] = Field(report, "warnings");
  return row;
}

std::string CampaignCsv(const std::vector<nlohmann::ordered_json>& rows) {
  std::vector<std::string> columns;
  for (const auto& row : rows)
    for (const auto& [key, value] : row.items())
      if (std::find(columns.begin(), columns.end(), key) == columns.end()) columns.push_back(key);
  std::string csv;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (i) csv += ',';
    csv += columns[i];
  }
  csv += '\n';
  for (const auto& row : rows) {
    for (size_t i = 0; i < columns.size(); ++i) {
      if (i) csv += ',';
      csv += CsvCell(row.contains(columns[i]) ? row[columns[i]] : nlohmann::ordered_json());
    }
    csv += '\n';
  }
  return csv;
}

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};

// The DEM's outline in EPSG:4326, when it is in a projected CRS (GCPs); nullptr in L.
std::unique_ptr<OGRPolygon> FootprintWgs84(const std::string& dir,
                                           const OGRSpatialReference& wgs84) {
  const Result<Raster> dem = ReadGeoTiff(dir + "/products/dem.tif");
  if (!dem) return nullptr;
  const auto to_wgs84 = DemToWgs84(*dem, wgs84);
  if (!to_wgs84) return nullptr;
  const double x0 = dem->min_x_m, y1 = dem->max_y_m;
  const double x1 = x0 + dem->cols * dem->cell_m, y0 = y1 - dem->rows * dem->cell_m;
  OGRLinearRing ring;
  for (auto [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}, {x0, y0}})
    ring.addPoint(x, y);
  auto polygon = std::make_unique<OGRPolygon>();
  polygon->addRing(&ring);
  if (polygon->transform(to_wgs84.get()) != OGRERR_NONE) return nullptr;
  return polygon;
}

}  // namespace

Status WriteCampaignGeoPackage(const std::vector<nlohmann::ordered_json>& rows,
                               const std::vector<std::string>& station_dirs,
                               const std::string& file) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (!driver) return Error{"GDAL has no GPKG driver"};
  std::error_code ec;
  fs::remove(file, ec);
  std::unique_ptr<GDALDataset, DatasetCloser> ds(
      driver->Create(file.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) return Error{file + ": cannot create the GeoPackage"};
  OGRSpatialReference wgs84 = Wgs84();
  OGRLayer* points = ds->CreateLayer("stations", &wgs84, wkbPoint, nullptr);
  OGRLayer* footprints = ds->CreateLayer("dem_footprints", &wgs84, wkbPolygon, nullptr);
  if (!points || !footprints) return Error{file + ": cannot create its layers"};
  const std::vector<std::pair<const char*, OGRFieldType>> columns = {
      {"station", OFTString},
      {"line", OFTString},
      {"time_utc", OFTString},
      {"terrain_correction_mgal", OFTReal},
      {"terrain_correction_sigma_mgal", OFTReal},
      {"coverage_30m", OFTReal},
      {"verdict", OFTString}};
  for (const auto& [name, type] : columns) {
    OGRFieldDefn field(name, type);
    if (points->CreateField(&field) != OGRERR_NONE) return Error{file + ": cannot add " + name};
  }
  OGRFieldDefn station_field("station", OFTString);
  footprints->CreateField(&station_field);
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    OGRFeature point(points->GetLayerDefn());
    for (const auto& [name, type] : columns) {
      const auto& v = row[name];
      if (v.is_string()) point.SetField(name, v.get<std::string>().c_str());
      if (v.is_number()) point.SetField(name, v.get<double>());
    }
    OGRPoint where;
    if (row["lat_deg"].is_number() && row["lon_deg"].is_number()) {
      where = OGRPoint(row["lon_deg"].get<double>(), row["lat_deg"].get<double>());
      point.SetGeometry(&where);
    }
    if (points->CreateFeature(&point) != OGRERR_NONE)
      return Error{file + ": cannot write a station"};
    if (std::unique_ptr<OGRPolygon> outline = FootprintWgs84(station_dirs[i], wgs84)) {
      OGRFeature footprint(footprints->GetLayerDefn());
      footprint.SetField("station", row["station"].get<std::string>().c_str());
      footprint.SetGeometry(outline.get());
      if (footprints->CreateFeature(&footprint) != OGRERR_NONE)
        return Error{file + ": cannot write a footprint"};
    }
  }
  return {};
}

}  // namespace ts
