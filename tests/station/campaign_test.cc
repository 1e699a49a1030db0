// The campaign table and GeoPackage against the stations' own JSON: three stations (one
// georeferenced DEM, one with a GNSS position, one not processed), read back as CSV and with
// GDAL.
#include "station/campaign.h"

#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <fstream>

#include "processing/io/raster.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

namespace fs = std::filesystem;

void WriteJson(const std::string& file, const nlohmann::json& j) {
  fs::create_directories(fs::path(file).parent_path());
  std::ofstream(file) << j.dump(2);
}

// A station as the pipeline leaves it: manifest, crew fields, report, terrain correction.
void MakeStation(const std::string& dir, const std::string& id, double tc, bool processed,
                 const nlohmann::json& gnss) {
  // The instrument height 1.52 m: L's origin 0.12 m under the taped tilt axis.
  const nlohmann::json stage = {{"height_above_mark_m", 1.40},
                                {"tilt_axis_offset_m", {0.0, 0.02, 0.12}}};
  WriteJson(dir + "/station.json", {{"station_id", id},
                                    {"created_utc", "2026-11-25T08:00:00.000Z"},
                                    {"calibration", {{"stage", stage}}},
                                    {"pairs", {{{"captured_utc", "2026-11-25T08:01:00.000Z"}}}}});
  nlohmann::json fields = {{"line", "L7"}, {"operator", "a, b"}};
  if (!gnss.is_null()) fields["gnss"] = gnss;
  WriteJson(dir + "/station_fields.json", fields);
  if (!processed) return;
  WriteJson(dir + "/products/report.json",
            {{"terrain_correction_mgal", tc},
             {"terrain_correction_sigma_mgal", 0.004},
             {"verdict", "usable"},
             {"warnings", {"ring 20-30 m: 80 % covered", "pair 3, \"dark\""}},
             {"dem", {{"coverage_30m", 0.93}}},
             {"calibration", {{"source", "station.json (stage self-calibrated)"}}}});
  WriteJson(dir + "/products/terrain_correction.json",
            {{"density_g_cm3", 2.67},
             {"verdict", "usable"},
             {"station_mark", {465030.0, 5260030.0, 412.5}},  // in the DEM's frame
             {"sigma_mgal", 0.004},
             {"rings",
              {{{"inner_m", 0.0}, {"outer_m", 2.0}, {"mgal", 0.001}},
               {{"inner_m", 2.0}, {"outer_m", 10.0}, {"mgal", tc - 0.001}},
               {{"inner_m", 50.0}, {"outer_m", "end of DEM"}, {"mgal", 0.0}}}}});
}

TEST(Campaign, OneRowPerStationFromItsOwnJsonAndAGeoPackageQgisCanOpen) {
  testing::TempDir dir;
  MakeStation(dir / "stations/G1", "G1", 0.041, true, {{"lat_deg", 47.5}, {"lon_deg", 8.25}});
  MakeStation(dir / "stations/G2", "G2", 0.012, true, nullptr);
  MakeStation(dir / "stations/G3", "G3", 0.0, false, nullptr);
  // G2's DEM georeferenced (GCPs): UTM 32N, 60 m square.
  Raster dem = Raster::Make(465000.0, 5260060.0, 1.0, 60, 60);
  OGRSpatialReference utm;
  utm.importFromEPSG(32632);
  char* wkt = nullptr;
  utm.exportToWkt(&wkt);
  dem.crs_wkt = wkt;
  CPLFree(wkt);
  ASSERT_TRUE(WriteGeoTiff(dem, dir / "stations/G2/products/dem.tif").ok());

  const Result<std::vector<std::string>> stations = FindStations({dir / "stations"});
  ASSERT_TRUE(stations.ok()) << stations.error();
  ASSERT_EQ(stations->size(), 3u);
  std::vector<nlohmann::ordered_json> rows;
  for (const std::string& s : *stations) rows.push_back(*CampaignRow(s));
  EXPECT_EQ(rows[0]["station"], "G1");
  EXPECT_EQ(rows[0]["line"], "L7");
  EXPECT_EQ(rows[0]["time_utc"], "2026-11-25T08:01:00.000Z");
  EXPECT_EQ(rows[0]["instrument_height_m"], 1.52);
  EXPECT_EQ(rows[0]["terrain_correction_mgal"], 0.041);
  EXPECT_EQ(rows[0]["ring_2_10_mgal"], 0.040);
  EXPECT_EQ(rows[0]["ring_50_end_mgal"], 0.0);
  EXPECT_EQ(rows[0]["position_source"], "GNSS");
  // G2's position from its georeferenced DEM: the mark at UTM 32N 465030 E 5260030 N is
  // 8.53573713 E 47.49276401 N (gdaltransform -s_srs EPSG:32632 -t_srs EPSG:4326).
  EXPECT_EQ(rows[1]["position_source"], "GCPs");
  EXPECT_NEAR(rows[1]["lon_deg"].get<double>(), 8.53573713472104, 1e-9);
  EXPECT_NEAR(rows[1]["lat_deg"].get<double>(), 47.4927640114573, 1e-9);
  EXPECT_EQ(rows[1]["height_m"], 412.5);
  EXPECT_EQ(rows[0]["verdict"], "good");  // sigma 0.004 within the default 0.01 mGal
  EXPECT_EQ(rows[2]["verdict"], "not processed");
  EXPECT_TRUE(rows[2]["terrain_correction_mgal"].is_null());

  const std::string csv = CampaignCsv(rows);
  std::istringstream lines(csv);
  std::string header, g1;
  std::getline(lines, header);
  std::getline(lines, g1);
  EXPECT_EQ(header.rfind("station,line,time_utc,instrument_height_m,lat_deg,lon_deg", 0), 0u)
      << header;
  EXPECT_NE(g1.find(",0.041,0.004,"), std::string::npos) << g1;
  EXPECT_NE(g1.find("\"ring 20-30 m: 80 % covered | pair 3, \"\"dark\"\"\""), std::string::npos)
      << g1;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);

  const std::string gpkg = dir / "campaign.gpkg";
  ASSERT_TRUE(WriteCampaignGeoPackage(rows, *stations, gpkg).ok());
  GDALAllRegister();
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(gpkg.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  ASSERT_TRUE(ds);
  OGRLayer* points = ds->GetLayerByName("stations");
  ASSERT_TRUE(points);
  EXPECT_EQ(points->GetFeatureCount(), 3);
  std::unique_ptr<OGRFeature> first(points->GetNextFeature());
  EXPECT_STREQ(first->GetFieldAsString("station"), "G1");
  EXPECT_DOUBLE_EQ(first->GetFieldAsDouble("terrain_correction_mgal"), 0.041);
  const OGRPoint* where = first->GetGeometryRef()->toPoint();
  EXPECT_DOUBLE_EQ(where->getX(), 8.25);
  EXPECT_DOUBLE_EQ(where->getY(), 47.5);
  OGRLayer* footprints = ds->GetLayerByName("dem_footprints");
  ASSERT_TRUE(footprints);
  ASSERT_EQ(footprints->GetFeatureCount(), 1);  // only G2's DEM is in a CRS
  std::unique_ptr<OGRFeature> outline(footprints->GetNextFeature());
  EXPECT_STREQ(outline->GetFieldAsString("station"), "G2");
  OGREnvelope e;
  outline->GetGeometryRef()->getEnvelope(&e);
  // The DEM's south-west corner, UTM 32N 465000 E 5260000 N, is 8.535341 E 47.492492 N
  // (gdaltransform -s_srs EPSG:32632 -t_srs EPSG:4326).
  EXPECT_NEAR(e.MinX, 8.535341, 1e-5);
  EXPECT_NEAR(e.MinY, 47.492492, 1e-5);
  EXPECT_NEAR((e.MaxY - e.MinY) * 111320.0, 60.0, 1.0);
}

TEST(Campaign, ADirectoryWithoutStationsIsOneErrorNamingIt) {
  testing::TempDir dir;
  fs::create_directories(dir / "empty");
  const Result<std::vector<std::string>> none = FindStations({dir / "empty"});
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().find(dir / "empty"), std::string::npos);
  EXPECT_FALSE(FindStations({dir / "missing"}).ok());
}

}  // namespace
}  // namespace ts
