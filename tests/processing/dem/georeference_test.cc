#include "processing/dem/georeference.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

Georeference Known() {
  Georeference g;
  g.scale = 0.9996;  // UTM's central scale factor
  g.rotation_rad = 0.4;
  g.shift_m = {512345.6, 5403210.9};
  g.height_offset_m = 287.25;
  return g;
}

std::vector<GroundControlPoint> Gcps(const Georeference& truth, int n) {
  const std::vector<Eigen::Vector3d> local = {
      {10, 5, -1.2}, {-20, 18, 0.5}, {3, -25, -2.0}, {25, 25, 1.0}};
  std::vector<GroundControlPoint> gcps;
  for (int i = 0; i < n; ++i)
    gcps.push_back({std::string(1, static_cast<char>('A' + i)), local[i], truth.ToWorld(local[i])});
  return gcps;
}

TEST(Georeference, TwoGcpsFixTheKnownTransform) {
  const Georeference truth = Known();
  const auto fit = FitGeoreference(Gcps(truth, 2), "");
  ASSERT_TRUE(fit) << fit.error();
  EXPECT_NEAR(fit->scale, truth.scale, 1e-9);
  EXPECT_NEAR(fit->rotation_rad, truth.rotation_rad, 1e-9);
  EXPECT_NEAR((fit->shift_m - truth.shift_m).norm(), 0.0, 1e-6);
  EXPECT_NEAR(fit->height_offset_m, truth.height_offset_m, 1e-9);
  const Eigen::Vector3d p(-7, 13, 2);
  EXPECT_NEAR((fit->ToWorld(p) - truth.ToWorld(p)).norm(), 0.0, 1e-6);
}

TEST(Georeference, FourNoisyGcpsFitInTheLeastSquaresSense) {
  const Georeference truth = Known();
  std::vector<GroundControlPoint> gcps = Gcps(truth, 4);
  const double noise[4][3] = {
      {0.02, -0.01, 0.03}, {-0.02, 0.01, -0.03}, {0.01, 0.02, 0.01}, {-0.01, -0.02, -0.01}};
  for (int i = 0; i < 4; ++i) gcps[i].world_m += Eigen::Vector3d(noise[i]);
  const auto fit = FitGeoreference(gcps, "");
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->rotation_rad, truth.rotation_rad, 1e-3);
  EXPECT_NEAR(fit->height_offset_m, truth.height_offset_m, 1e-9);  // the noise sums to zero
  ASSERT_EQ(fit->residuals_m.size(), 4u);
  for (double r : fit->residuals_m) EXPECT_LT(r, 0.06);
}

TEST(Georeference, RefusesTooFewOrCoincidentGcps) {
  EXPECT_FALSE(FitGeoreference(Gcps(Known(), 1), ""));
  std::vector<GroundControlPoint> same = Gcps(Known(), 2);
  same[1].station_m.head<2>() = same[0].station_m.head<2>();
  const auto fit = FitGeoreference(same, "");
  ASSERT_FALSE(fit);
  EXPECT_NE(fit.error().find("undetermined"), std::string::npos);
}

TEST(Georeference, ReadsAGcpFileWithItsCrs) {
  testing::TempDir dir;
  const Georeference truth = Known();
  const auto gcps = Gcps(truth, 3);
  std::ofstream f(dir / "gcps.yaml");
  f.precision(12);
  f << "crs: EPSG:32633\npoints:\n";
  for (const auto& g : gcps)
    f << "  - {name: " << g.name << ", station: [" << g.station_m.x() << ", " << g.station_m.y()
      << ", " << g.station_m.z() << "], world: [" << g.world_m.x() << ", " << g.world_m.y() << ", "
      << g.world_m.z() << "]}\n";
  f.close();
  const auto fit = LoadGeoreference(dir / "gcps.yaml");
  ASSERT_TRUE(fit) << fit.error();
  EXPECT_NE(fit->crs_wkt.find("UTM zone 33N"), std::string::npos);
  EXPECT_NEAR(fit->rotation_rad, 0.4, 1e-6);
}

TEST(Georeference, BadGcpFilesNameTheFileAndField) {
  testing::TempDir dir;
  auto error_of = [&](const std::string& text) {
    std::ofstream(dir / "g.yaml") << text;
    const auto r = LoadGeoreference(dir / "g.yaml");
    EXPECT_FALSE(r);
    return r ? std::string() : r.error();
  };
  EXPECT_NE(error_of("points: []\n").find("g.yaml: crs"), std::string::npos);
  EXPECT_NE(error_of("crs: EPSG:4326\npoints: []\n").find("not a projected CRS"),
            std::string::npos);
  EXPECT_NE(error_of("crs: NOT-A-CRS\n").find("crs: GDAL does not know"), std::string::npos);
  EXPECT_NE(error_of("crs: EPSG:32633\npoints:\n  - {station: [1, 2], world: [1, 2, 3]}\n")
                .find("points[0].station"),
            std::string::npos);
  EXPECT_NE(error_of("crs: EPSG:32633\npoints:\n  - {station: [1, 2, 3], world: [1, 2, .nan]}\n")
                .find("points[0].world: must be finite"),
            std::string::npos);
  EXPECT_NE(error_of("crs: EPSG:32633\npoints:\n  - {station: [1, 2, 3], world: [1, 2, 3]}\n")
                .find("at least two GCPs"),
            std::string::npos);
  EXPECT_NE(LoadGeoreference(dir / "none.yaml").error().find("none.yaml"), std::string::npos);
}

}  // namespace
}  // namespace ts
