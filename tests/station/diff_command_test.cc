// `topostation diff` on bare GeoTIFF DEMs through the real command line (station directories:
// the two-epoch survey test).
#include <gtest/gtest.h>

#include <ogr_spatialref.h>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "processing/io/raster.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using testing::RunCommand;

std::string Diff(const std::string& args) {
  return std::string(TS_TOPOSTATION_EXE) + " diff " + args + " 2>&1";
}

// A 40 m square: a plane, and the same plane with a 2 x 3 m pit 0.5 m deep.
void WriteEpochs(const std::filesystem::path& dir, bool with_std) {
  Raster before = Raster::Make(-20, 20, 1.0, 40, 40);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) before.at(r, c) = static_cast<float>(50.0 + 0.1 * c);
  Raster after = before;
  for (int r = 10; r < 13; ++r)
    for (int c = 5; c < 7; ++c) after.at(r, c) -= 0.5f;
  ASSERT_TRUE(WriteGeoTiff(before, dir / "before.tif"));
  ASSERT_TRUE(WriteGeoTiff(after, dir / "after.tif"));
  if (!with_std) return;
  Raster s = before;
  std::fill(s.values.begin(), s.values.end(), 0.02f);
  ASSERT_TRUE(WriteGeoTiff(s, dir / "before_std.tif"));
  ASSERT_TRUE(WriteGeoTiff(s, dir / "after_std.tif"));
}

TEST(DiffCommand, GeoTiffsWithTheirStdGrids) {
  testing::TempDir dir;
  WriteEpochs(dir.path(), true);
  const auto r = RunCommand(Diff((dir / "before.tif") + " " + (dir / "after.tif") + " --out " +
                                 (dir / "change") + " --json"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["before"]["std"], dir / "before_std.tif");
  EXPECT_EQ(j["lowering"]["cells"], 6);
  EXPECT_NEAR(j["lowering"]["volume_m3"].get<double>(), 3.0, 1e-4);
  EXPECT_NEAR(j["lowering"]["sigma_m3"].get<double>(), std::sqrt(6.0) * std::sqrt(2.0) * 0.02,
              1e-6);
  EXPECT_NEAR(j["max_subsidence"]["depth_m"].get<double>(), 0.5, 1e-5);
  EXPECT_NEAR(j["max_subsidence"]["sigma_m"].get<double>(), std::sqrt(2.0) * 0.02, 1e-6);
  ASSERT_EQ(j["subsidence_regions"].size(), 1u);
  EXPECT_NEAR(j["subsidence_regions"][0]["area_m2"].get<double>(), 6.0, 1e-9);
  EXPECT_EQ(j["level_of_detection"]["t_critical"], 1.96);
  // The products: the DoD itself, its std, the picture, the JSON and the GeoJSON.
  const Result<Raster> dod = ReadGeoTiff(dir / "change/dod.tif");
  ASSERT_TRUE(dod) << dod.error();
  EXPECT_NEAR(dod->at(11, 5), -0.5, 1e-6);
  EXPECT_NEAR(dod->at(20, 20), 0.0, 1e-6);
  const Result<Raster> dod_std = ReadGeoTiff(dir / "change/dod_std.tif");
  ASSERT_TRUE(dod_std);
  EXPECT_NEAR(dod_std->at(0, 0), std::sqrt(2.0) * 0.02, 1e-6);
  const cv::Mat png = cv::imread(dir / "change/dod.png");
  ASSERT_FALSE(png.empty());
  const cv::Vec3b pit = png.at<cv::Vec3b>(11 * 8 + 4, 5 * 8 + 4);  // BGR: red
  EXPECT_GT(pit[2], 150);
  EXPECT_LT(pit[0], 100);
  std::ifstream geojson(dir / "change/subsidence.geojson");
  const auto g = nlohmann::json::parse(geojson);
  EXPECT_EQ(g["type"], "FeatureCollection");
  EXPECT_EQ(g["features"].size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(dir / "change/change.json"));
}

// Without std grids a fixed level of detection is needed; with it the pit is found.
TEST(DiffCommand, FixedLevelOfDetectionWithoutStdGrids) {
  testing::TempDir dir;
  WriteEpochs(dir.path(), false);
  const std::string args =
      (dir / "before.tif") + " " + (dir / "after.tif") + " --out " + (dir / "change");
  auto r = RunCommand(Diff(args));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("before.tif: no standard deviation grid"), std::string::npos) << r.out;
  r = RunCommand(Diff(args + " --lod 0.1"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("lowering 6 m2, 3.00"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max subsidence 0.500"), std::string::npos) << r.out;
}

// A looser test than the regions' growth (t 0.8 < 1) is taken as it is, not refused.
TEST(DiffCommand, LooseTCritical) {
  testing::TempDir dir;
  WriteEpochs(dir.path(), true);
  const auto r = RunCommand(Diff((dir / "before.tif") + " " + (dir / "after.tif") + " --out " +
                                 (dir / "change") + " --t-critical 0.8 --json"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["lowering"]["cells"], 6);
}

std::string Wkt(int epsg) {
  OGRSpatialReference s;
  s.importFromEPSG(epsg);
  char* wkt = nullptr;
  s.exportToWkt(&wkt);
  const std::string out = wkt;
  CPLFree(wkt);
  return out;
}

// Georeferenced epochs (processed with GCPs) in one projected CRS, on grids offset by half a
// cell: compared after resampling, the regions' GeoJSON names the CRS; another CRS is refused.
TEST(DiffCommand, GeoreferencedEpochs) {
  testing::TempDir dir;
  Raster before = Raster::Make(500000, 5400040, 1.0, 40, 40, 200.0f);
  before.crs_wkt = Wkt(32633);
  Raster after = Raster::Make(500000.5, 5400039.5, 1.0, 40, 40, 200.0f);
  after.crs_wkt = before.crs_wkt;
  for (int r = 10; r < 20; ++r)
    for (int c = 10; c < 20; ++c) after.at(r, c) = 199.0f;  // a 10 x 10 m pit, 1 m deep
  Raster s = before;
  std::fill(s.values.begin(), s.values.end(), 0.02f);
  ASSERT_TRUE(WriteGeoTiff(before, dir / "e1.tif"));
  ASSERT_TRUE(WriteGeoTiff(s, dir / "e1_std.tif"));
  ASSERT_TRUE(WriteGeoTiff(after, dir / "e2.tif"));
  s.min_x_m = after.min_x_m, s.max_y_m = after.max_y_m;
  ASSERT_TRUE(WriteGeoTiff(s, dir / "e2_std.tif"));
  const auto r = RunCommand(
      Diff((dir / "e1.tif") + " " + (dir / "e2.tif") + " --out " + (dir / "change") + " --json"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["after_resampled_onto_before"].get<bool>());
  EXPECT_NE(j["frame"].get<std::string>().find("UTM zone 33N"), std::string::npos) << j["frame"];
  // Bilinear resampling spreads the pit's edges over half a cell: the volume is kept.
  EXPECT_NEAR(j["subsidence_regions"][0]["volume_m3"].get<double>(), 100.0, 3.0);
  std::ifstream geojson(dir / "change/subsidence.geojson");
  const auto g = nlohmann::json::parse(geojson);
  EXPECT_EQ(g["crs"]["properties"]["name"], "urn:ogc:def:crs:EPSG::32633");
  const auto& ring = g["features"][0]["geometry"]["coordinates"][0];
  EXPECT_GT(ring[0][0].get<double>(), 500000.0);
  EXPECT_GT(ring[0][1].get<double>(), 5400000.0);

  after.crs_wkt = Wkt(32634);
  ASSERT_TRUE(WriteGeoTiff(after, dir / "e2.tif"));
  const auto refused =
      RunCommand(Diff((dir / "e1.tif") + " " + (dir / "e2.tif") + " --out " + (dir / "change")));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.out.find("e2.tif: in CRS"), std::string::npos) << refused.out;
}

TEST(DiffCommand, BadInputGivesOneClearError) {
  testing::TempDir dir;
  WriteEpochs(dir.path(), true);
  auto error_of = [&](const std::string& args) {
    const auto r = RunCommand(Diff(args + " --out " + (dir / "out")));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    return r.out;
  };
  EXPECT_NE(error_of((dir / "before.tif") + " " + (dir / "none.tif")).find("none.tif"),
            std::string::npos);
  std::ofstream(dir / "text.tif") << "not a raster\n";
  EXPECT_NE(error_of((dir / "text.tif") + " " + (dir / "after.tif")).find("text.tif"),
            std::string::npos);
  Raster far = Raster::Make(500, 500, 1.0, 10, 10, 1.0f);
  ASSERT_TRUE(WriteGeoTiff(far, dir / "far.tif"));
  EXPECT_NE(error_of((dir / "before.tif") + " " + (dir / "far.tif") + " --lod 0.1")
                .find("far.tif: does not overlap"),
            std::string::npos);
  EXPECT_NE(error_of(dir.path().string() + " " + (dir / "after.tif")).find("products/dem.tif"),
            std::string::npos);
  EXPECT_NE(error_of((dir / "before.tif") + " " + (dir / "after.tif") + " --t-critical -2")
                .find("t_critical"),
            std::string::npos);
  // A std grid that does not match its DEM.
  ASSERT_TRUE(WriteGeoTiff(Raster::Make(0, 0, 1.0, 3, 3, 0.1f), dir / "after_std.tif"));
  EXPECT_NE(error_of((dir / "before.tif") + " " + (dir / "after.tif")).find("after_std.tif"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "out/change.json"));
}

}  // namespace
}  // namespace ts
