// `topostation terrain-correction` on a bare GeoTIFF DEM, through the real command line.
#include <gtest/gtest.h>

#include <ogr_spatialref.h>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "processing/gravity/prism.h"
#include "processing/io/raster.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using testing::RunCommand;

// An inclined plane 100 m above the datum through the station (the exact value: see
// terrain_correction_test.cc).
TEST(TerrainCorrectionCommand, InclinedPlaneGeoTiffAgainstTheExactValue) {
  testing::TempDir dir;
  const double t = std::tan(15 * M_PI / 180.0);
  Raster dem = Raster::Make(-35, 35, 1.0, 70, 70);
  for (int r = 0; r < 70; ++r)
    for (int c = 0; c < 70; ++c) dem.at(r, c) = static_cast<float>(100.0 + dem.CellCentreX(c) * t);
  ASSERT_TRUE(WriteGeoTiff(dem, dir / "plane.tif"));
  double integral = 0.0;
  for (int k = 0; k < 100000; ++k) {
    const double c = std::cos((k + 0.5) * 2 * M_PI / 100000);
    integral += (1.0 - 1.0 / std::sqrt(1.0 + t * t * c * c)) * 2 * M_PI / 100000;
  }
  for (double density : {2.67, 2.0}) {
    const double exact = kGravitationalConstant * density * 1000 * kMgalPerMs2 * 30.0 * integral;
    const auto r =
        RunCommand(std::string(TS_TOPOSTATION_EXE) + " terrain-correction " + (dir / "plane.tif") +
                   " --station 0,0 --radius 30 --density " + std::to_string(density) + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_NEAR(j["terrain_correction_mgal"].get<double>(), exact, 0.02 * exact);
    EXPECT_NEAR(j["station_mark"][2].get<double>(), 100.0, 1e-4);  // height from the DEM
    EXPECT_EQ(j["rings"].size(), 6u);
    EXPECT_TRUE(std::filesystem::exists(dir / "terrain_correction.json"));
  }
}

TEST(TerrainCorrectionCommand, BadInputGivesOneClearError) {
  testing::TempDir dir;
  ASSERT_TRUE(WriteGeoTiff(Raster::Make(0, 10, 1.0, 10, 10, 5.0f), dir / "d.tif"));
  auto error_of = [](const std::string& args) {
    const auto r =
        RunCommand(std::string(TS_TOPOSTATION_EXE) + " terrain-correction " + args + " 2>&1");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    return r.out;
  };
  EXPECT_NE(error_of(dir / "d.tif").find("needs --station"), std::string::npos);
  EXPECT_NE(error_of((dir / "d.tif") + " --station 50,50").find("no height at the station"),
            std::string::npos);
  EXPECT_NE(error_of((dir / "d.tif") + " --station 5,5 --density -1").find("density"),
            std::string::npos);
  EXPECT_NE(error_of(dir / "none.tif").find("none.tif"), std::string::npos);
  EXPECT_NE(error_of(dir.path().string()).find("products/dem.tif"), std::string::npos);
  // A mark that is not a place: nan gave "nan +- nan mGal" with exit 0.
  EXPECT_NE(error_of((dir / "d.tif") + " --station nan,nan").find("must be finite numbers"),
            std::string::npos);
  EXPECT_NE(error_of((dir / "d.tif") + " --station 5,5 --station-z inf").find("finite"),
            std::string::npos);
  EXPECT_NE(error_of((dir / "d.tif") + " --station 5,5 --station-z 1e300")
                .find("--station-z 1e+300 m is a height no ground has"),
            std::string::npos);
  // A height no ground has (a float's 3e38: an undeclared nodata value).
  Raster spike = Raster::Make(0, 10, 1.0, 10, 10, 5.0f);
  spike.at(3, 4) = 3e38f;
  ASSERT_TRUE(WriteGeoTiff(spike, dir / "spike.tif"));
  EXPECT_NE(error_of((dir / "spike.tif") + " --station 5,5")
                .find("spike.tif: cell (row 3, column 4) holds 3e+38 m, a height no ground has"),
            std::string::npos);
  // Degrees taken for metres: a DEM in EPSG:4326 is refused, naming the file and the cure.
  Raster degrees = Raster::Make(10.0, 47.0, 1e-5, 10, 10, 5.0f);
  OGRSpatialReference wgs84;
  wgs84.importFromEPSG(4326);
  char* wkt = nullptr;
  wgs84.exportToWkt(&wkt);
  degrees.crs_wkt = wkt;
  CPLFree(wkt);
  ASSERT_TRUE(WriteGeoTiff(degrees, dir / "geographic.tif"));
  const std::string geographic = error_of((dir / "geographic.tif") + " --station 10,47");
  EXPECT_NE(geographic.find("geographic.tif: its CRS (WGS 84) is geographic, in degrees"),
            std::string::npos)
      << geographic;
}

// Reading a station is not writing into it: its products/terrain_correction.json is process's
// (with the ground nobody saw as one unknown), and a recomputation from the bare dem.tif
// overwrote it.
TEST(TerrainCorrectionCommand, AStationsOwnProductIsNeverOverwritten) {
  testing::TempDir dir;
  const std::filesystem::path products = dir.path() / "S" / "products";
  std::filesystem::create_directories(products);
  std::ofstream(dir.path() / "S" / "station.json") << "{}";
  std::ofstream(products / "terrain_correction.json") << "process's own";
  Raster dem = Raster::Make(-30, 30, 1.0, 60, 60, 5.0f);
  dem.at(10, 10) = 9.0f;
  ASSERT_TRUE(WriteGeoTiff(dem, (products / "dem.tif").string()));
  const auto r = RunCommand(std::string(TS_TOPOSTATION_EXE) + " terrain-correction " +
                            (products / "dem.tif").string() + " --station 0,0 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("not written into the station (give --out)"), std::string::npos) << r.out;
  std::ifstream kept(products / "terrain_correction.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "process's own");
  const auto out = RunCommand(std::string(TS_TOPOSTATION_EXE) + " terrain-correction " +
                              (products / "dem.tif").string() + " --station 0,0 --out " +
                              (dir / "mine.json") + " 2>&1");
  ASSERT_EQ(out.exit_code, 0) << out.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "mine.json"));
}

}  // namespace
}  // namespace ts
