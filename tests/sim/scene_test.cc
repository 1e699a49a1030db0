#include "sim/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "processing/io/raster.h"
#include "sim/scene_mesh.h"
#include "tests/common/temp_dir.h"

namespace ts::sim {
namespace {

// Mean slope magnitude (rise over run) of the terrain inside a square, by finite differences.
double MeanSlope(const Scene& s, double half_m) {
  double sum = 0.0;
  int n = 0;
  for (double y = -half_m; y <= half_m; y += 1.0) {
    for (double x = -half_m; x <= half_m; x += 1.0) {
      const double gx = (s.TerrainHeight(x + 0.5, y) - s.TerrainHeight(x - 0.5, y));
      const double gy = (s.TerrainHeight(x, y + 0.5) - s.TerrainHeight(x, y - 0.5));
      sum += std::hypot(gx, gy);
      ++n;
    }
  }
  return sum / n;
}

TEST(Scene, EveryBuiltinSceneIsLargeEnoughAndHasTheMarkBelowTheStage) {
  for (const std::string& name : BuiltinSceneNames()) {
    const Result<Scene> s = MakeBuiltinScene(name, 7);
    ASSERT_TRUE(s.ok()) << name;
    EXPECT_GE(2 * s->half_extent_m, 120.0) << name;
    EXPECT_NEAR(s->TerrainHeight(0, 0), -s->stage_height_m, 1e-6) << name;
    EXPECT_TRUE(std::isnan(s->TerrainHeight(s->half_extent_m + 1, 0)));
  }
  EXPECT_FALSE(MakeBuiltinScene("moon", 1).ok());
  EXPECT_NE(MakeBuiltinScene("moon", 1).error().find("flat, hills"), std::string::npos);
}

TEST(Scene, DeterministicPerSeed) {
  const Scene a = *MakeBuiltinScene("rough", 3), b = *MakeBuiltinScene("rough", 3);
  const Scene c = *MakeBuiltinScene("rough", 4);
  EXPECT_EQ(a.heights, b.heights);
  EXPECT_NE(a.heights, c.heights);
}

TEST(Scene, ReliefMatchesTheSceneDescriptions) {
  EXPECT_LT(MeanSlope(*MakeBuiltinScene("flat", 1), 30), 0.02);  // < 2 %
  const Scene slope = *MakeBuiltinScene("slope", 1);
  const double degrees = std::atan(MeanSlope(slope, 30)) * 180.0 / M_PI;
  EXPECT_GT(degrees, 14.0);
  EXPECT_LT(degrees, 27.0);
  // Hills: a few metres of relief in the 60 m square.
  const Scene hills = *MakeBuiltinScene("hills", 1);
  double lo = 1e9, hi = -1e9;
  for (double y = -30; y <= 30; y += 1)
    for (double x = -30; x <= 30; x += 1)
      lo = std::min(lo, hills.TerrainHeight(x, y)), hi = std::max(hi, hills.TerrainHeight(x, y));
  EXPECT_GT(hi - lo, 2.0);
  EXPECT_LT(hi - lo, 20.0);
}

TEST(Scene, ForestCoversTwentyToFortyPercentAndLeavesTheStationClear) {
  const Scene forest = *MakeBuiltinScene("forest", 2);
  int covered = 0, cells = 0;
  for (double y = -59.5; y < 60; y += 1)
    for (double x = -59.5; x < 60; x += 1) covered += forest.ObjectCovers(x, y), ++cells;
  const double cover = static_cast<double>(covered) / cells;
  EXPECT_GE(cover, 0.20);
  EXPECT_LE(cover, 0.40);
  for (double a = 0; a < 6.28; a += 0.1)
    EXPECT_FALSE(forest.ObjectCovers(2.5 * std::cos(a), 2.5 * std::sin(a)));
  for (const SceneObject& o : forest.objects)
    EXPECT_NEAR(o.ground.z(), forest.TerrainHeight(o.ground.x(), o.ground.y()), 1e-6);
}

TEST(Scene, TerrainIsThePiecewisePlanarLatticeSurface) {
  const Scene s = *MakeBuiltinScene("rough", 5);
  // Exact at the vertices.
  for (int i = 10; i < s.n; i += 97)
    EXPECT_DOUBLE_EQ(s.TerrainHeight(s.LatticeX(i), s.LatticeX(i / 2)), s.lattice(i, i / 2));
  // Inside one triangle the surface is planar: the midpoint equals the mean of the ends.
  const SceneMesh mesh = BuildSceneMesh(s);
  for (double x = -20.1; x < 20; x += 3.3) {
    const double y = 0.4 * x + 0.07;
    int ix, iy, half;
    ASSERT_TRUE(s.LocateTriangle(x, y, &ix, &iy, &half));
    const int t = SceneMesh::TerrainTriangle(s, ix, iy, half);
    const Eigen::Vector3d p(x, y, s.TerrainHeight(x, y));
    EXPECT_NEAR(mesh.normals[t].dot(p), mesh.plane_offsets[t], 1e-9);
    EXPECT_GT(mesh.normals[t].z(), 0.0);
  }
}

TEST(Scene, TerrainFromAGeoTiffDem) {
  testing::TempDir dir;
  // A plane z = 100 + 0.1 x - 0.05 y on 0.5 m cells, 160 m square centred on (5000, 7000).
  Raster dem = Raster::Make(4920, 7080, 0.5, 320, 320);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      dem.at(r, c) = static_cast<float>(100 + 0.1 * (dem.CellCentreX(c) - 5000) -
                                        0.05 * (dem.CellCentreY(r) - 7000));
  ASSERT_TRUE(WriteGeoTiff(dem, dir / "plane.tif").ok());
  const Result<Scene> s = MakeSceneFromDem(dir / "plane.tif", 1);
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_NEAR(s->TerrainHeight(0, 0), -1.5, 1e-4);
  EXPECT_NEAR(s->TerrainHeight(20, -10), -1.5 + 2.0 + 0.5, 1e-3);
  // Too small, or not a DEM at all.
  const Raster small = Raster::Make(0, 40, 1, 40, 40, 1.0f);
  ASSERT_TRUE(WriteGeoTiff(small, dir / "small.tif").ok());
  EXPECT_NE(MakeSceneFromDem(dir / "small.tif", 1).error().find("needs at least 64"),
            std::string::npos);
  std::ofstream(dir / "junk.tif") << "not a tiff";
  EXPECT_NE(MakeSceneFromDem(dir / "junk.tif", 1).error().find("junk.tif: not a raster"),
            std::string::npos);
}

}  // namespace
}  // namespace ts::sim

namespace ts::sim {
namespace {

// A later epoch: the ground sinks by exactly the raised-cosine bowl, objects on it with it,
// and the lattice holds the closed-form volume.
TEST(SceneEpoch, SubsidenceBowlLowersTheGroundByItsProfile) {
  Scene before = MakeBuiltinScene("forest", 3).value();
  Scene after = before;
  Subsidence bowl;
  bowl.centre_m = {12.0, -8.0};
  bowl.radius_m = 6.0;
  bowl.depth_m = 0.7;
  ASSERT_TRUE(ApplySubsidence(&after, bowl));
  EXPECT_NEAR(after.TerrainHeight(12.0, -8.0), before.TerrainHeight(12.0, -8.0) - 0.7, 1e-5);
  EXPECT_NEAR(after.TerrainHeight(15.0, -8.0), before.TerrainHeight(15.0, -8.0) - 0.35, 1e-5);
  EXPECT_EQ(after.TerrainHeight(19.0, -8.0), before.TerrainHeight(19.0, -8.0));
  EXPECT_EQ(after.TerrainHeight(0.0, 0.0), before.TerrainHeight(0.0, 0.0));
  double volume = 0.0;
  for (int iy = 0; iy < after.n; ++iy)
    for (int ix = 0; ix < after.n; ++ix) volume += before.lattice(ix, iy) - after.lattice(ix, iy);
  volume *= after.spacing_m * after.spacing_m;
  EXPECT_NEAR(volume, bowl.Volume(), 0.002 * bowl.Volume());
  EXPECT_NEAR(bowl.Volume(), (0.5 - 2.0 / (M_PI * M_PI)) * M_PI * 0.7 * 36.0, 1e-12);
  for (size_t i = 0; i < after.objects.size(); ++i)
    EXPECT_NEAR(before.objects[i].ground.z() - after.objects[i].ground.z(),
                bowl.LoweringAt(after.objects[i].ground.x(), after.objects[i].ground.y()), 1e-9);
  ASSERT_EQ(after.subsidence.size(), 1u);

  bowl.centre_m = {4.0, 0.0};  // reaches within 1 m of the mark
  EXPECT_FALSE(ApplySubsidence(&after, bowl));
  bowl.centre_m = {30.0, 0.0};
  bowl.depth_m = -1.0;
  EXPECT_FALSE(ApplySubsidence(&after, bowl));
}

TEST(SceneEpoch, SunFromAzimuthAndElevation) {
  Scene s = MakeBuiltinScene("flat", 1).value();
  ASSERT_TRUE(SetSun(&s, 90.0, 30.0));  // east, 30 degrees up
  EXPECT_NEAR(s.lighting.to_sun.x(), std::cos(M_PI / 6), 1e-12);
  EXPECT_NEAR(s.lighting.to_sun.y(), 0.0, 1e-12);
  EXPECT_NEAR(s.lighting.to_sun.z(), 0.5, 1e-12);
  EXPECT_FALSE(SetSun(&s, 0.0, 2.0));
}

}  // namespace
}  // namespace ts::sim
