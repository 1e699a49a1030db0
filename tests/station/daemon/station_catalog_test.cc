#include "station/daemon/station_catalog.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts::daemon {
namespace {

namespace fs = std::filesystem;

TEST(StationCatalog, AProductIsAPlainFileInItsStationsProductsNeverAPath) {
  testing::TempDir dir;
  fs::create_directories(dir / "S1/products");
  std::ofstream(dir / "S1/station.json") << "{}";
  std::ofstream(dir / "S1/products/dem.tif") << "tif";
  std::ofstream(dir / "token") << "secret";
  fs::create_symlink(dir / "token", dir / "S1/products/leak.json");
  StationCatalog catalog(dir.path().string());
  ASSERT_TRUE(catalog.ProductPath("S1", "dem.tif").has_value());
  EXPECT_EQ(*catalog.ProductPath("S1", "dem.tif"), fs::canonical(dir / "S1/products/dem.tif"));
  for (const auto& [id, name] : std::vector<std::pair<std::string, std::string>>{
           {"S1", "../station.json"},
           {"S1", ".."},
           {"..", "token"},
           {"S1", "leak.json"},  // a link out of products/
           {"S1", "missing.tif"},
           {"S2", "dem.tif"}})
    EXPECT_FALSE(catalog.ProductPath(id, name).has_value()) << id << "/" << name;
}

TEST(StationCatalog, ListsStationsWithTheirTerrainCorrection) {
  testing::TempDir dir;
  fs::create_directories(dir / "S1/products");
  std::ofstream(dir / "S1/station.json") << R"({"created_utc": "2026-11-25T10:00:00Z",
                                               "capture_plan": [1, 2], "pairs": [1]})";
  std::ofstream(dir / "S1/products/report.json")
      << R"({"terrain_correction_mgal": 0.041, "terrain_correction_sigma_mgal": 0.006,
             "verdict": "usable"})";
  fs::create_directories(dir / "not a station");
  StationCatalog catalog(dir.path().string());
  const nlohmann::json list = catalog.List();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0]["id"], "S1");
  EXPECT_EQ(list[0]["pairs"], 1);
  EXPECT_EQ(list[0]["planned_pairs"], 2);
  EXPECT_EQ(list[0]["terrain_correction_mgal"], 0.041);
  EXPECT_EQ(list[0]["verdict"], "usable");
  EXPECT_FALSE(catalog.Get("S2").has_value());
  EXPECT_FALSE(catalog.Get("../S1").has_value());
  EXPECT_EQ((*catalog.Get("S1"))["products"], nlohmann::json::array({"report.json"}));
}

}  // namespace
}  // namespace ts::daemon
