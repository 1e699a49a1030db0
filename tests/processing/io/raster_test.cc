// Resampling a raster onto another grid, and onto a station frame whose azimuth stands
// elsewhere (a different pan zero): against planes whose values are known everywhere.
#include "processing/io/raster.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <utility>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

// A 41 x 41 raster of 1 m cells centred on the origin with z = f(x, y).
template <class F>
Raster Plane(F f) {
  Raster r;
  r.cols = r.rows = 41;
  r.cell_m = 1.0;
  r.min_x_m = -20.5;
  r.max_y_m = 20.5;
  r.values.resize(41 * 41);
  for (int row = 0; row < r.rows; ++row)
    for (int col = 0; col < r.cols; ++col)
      r.at(row, col) = static_cast<float>(f(r.CellCentreX(col), r.CellCentreY(row)));
  return r;
}

TEST(Raster, ResampledOntoAGridTurnedByAPanZeroSeesTheGroundTurned) {
  // Ground rising to the north (+Y). A frame whose azimuths stand 90 deg clockwise further
  // sees that rise at its azimuth 90: along +X.
  const Raster north = Plane([](double, double y) { return 0.1 * y; });
  Raster grid = Plane([](double, double) { return 0.0; });
  grid.cols = grid.rows = 21;  // inside the source, where every cell is interpolated
  grid.min_x_m = -10.5;
  grid.max_y_m = 10.5;
  grid.values.assign(21 * 21, 0.0f);
  const Raster same = north.ResampledOnto(grid);
  const Raster turned = north.ResampledOnto(grid, 90.0);
  const Raster slightly = north.ResampledOnto(grid, 0.94);
  const double s = std::sin(0.94 * M_PI / 180.0), c = std::cos(0.94 * M_PI / 180.0);
  for (int row = 0; row < grid.rows; ++row)
    for (int col = 0; col < grid.cols; ++col) {
      const double x = grid.CellCentreX(col), y = grid.CellCentreY(row);
      EXPECT_NEAR(same.at(row, col), 0.1 * y, 1e-5);
      EXPECT_NEAR(turned.at(row, col), 0.1 * x, 1e-5);
      // Turned by a: the source point is the grid point turned back by a (clockwise by -a).
      EXPECT_NEAR(slightly.at(row, col), 0.1 * (x * s + y * c), 1e-5);
    }
}

// A frame whose origin lies lower under the tilt axis sees every height higher by as much.
TEST(Raster, ResampledOntoAGridLiftedSeesTheGroundHigherByTheLift) {
  const Raster north = Plane([](double, double y) { return 0.1 * y - 1.5; });
  const Raster grid = Plane([](double, double) { return 0.0; });
  const Raster lifted = north.ResampledOnto(grid, 90.0, 0.0125);
  for (int row = 1; row + 1 < grid.rows; ++row)
    for (int col = 1; col + 1 < grid.cols; ++col)
      EXPECT_NEAR(lifted.at(row, col), 0.1 * grid.CellCentreX(col) - 1.5 + 0.0125, 1e-5);
}

// A mask sampled by the nearest cell keeps its edge where it was: the cells beside a gap keep
// their values, which bilinear sampling (NaN next to nodata) drops on one side. Turned by
// 90 deg, the gap at x = 3 stands at the grid's y = -3 (the grid's azimuth 90 is the mask's 0).
TEST(Raster, ResampledOntoByTheNearestCellKeepsTheCellsBesideAGap) {
  Raster mask = Plane([](double, double) { return 1.0; });
  int gap_row = 0, gap_col = 0;
  ASSERT_TRUE(mask.CellOf(3.0, 0.0, &gap_row, &gap_col));
  for (int row = 0; row < mask.rows; ++row) mask.at(row, gap_col) = Raster::kNoData;
  const Raster grid = Plane([](double, double) { return 0.0; });
  const Raster nearest = mask.ResampledOnto(grid, 0.0, 0.0, Raster::Sampling::kNearestCell);
  const Raster bilinear = mask.ResampledOnto(grid);
  const Raster turned = mask.ResampledOnto(grid, 90.0, 0.0, Raster::Sampling::kNearestCell);
  for (int row = 1; row + 1 < grid.rows; ++row)
    for (int col = 1; col + 1 < grid.cols; ++col) {
      const double x = grid.CellCentreX(col), y = grid.CellCentreY(row);
      EXPECT_EQ(Raster::IsNoData(nearest.at(row, col)), x == 3.0) << x << ", " << y;
      // A centre's bilinear square reaches east: the cell west of the gap falls with it.
      EXPECT_EQ(Raster::IsNoData(bilinear.at(row, col)), x == 2.0 || x == 3.0) << x << ", " << y;
      EXPECT_EQ(Raster::IsNoData(turned.at(row, col)), y == -3.0) << x << ", " << y;
    }
}

// Catmull-Rom reproduces a quadratic exactly, where bilinear interpolation cuts its chords
// (midway between two centres by an eighth of the second derivative times the cell squared);
// with a cell of no data among the sixteen it falls back to bilinear.
TEST(Raster, CubicInterpolationFollowsACurvedSurface) {
  auto bowl = [](double x, double y) { return 0.02 * x * x - 0.01 * x * y + 0.03 * y * y + 5; };
  Raster r = Plane(bowl);
  for (const auto& [x, y] : {std::pair{0.3, -0.2}, {4.9, 7.1}, {-12.25, 3.5}, {17.6, -18.4}}) {
    EXPECT_NEAR(r.InterpolateCubic(x, y), bowl(x, y), 1e-4) << x << ", " << y;
    EXPECT_GT(std::abs(r.Interpolate(x, y) - bowl(x, y)), 1e-3) << x << ", " << y;
  }
  int row = 0, col = 0;
  ASSERT_TRUE(r.CellOf(4.9, 7.1, &row, &col));
  // (4.9, 7.1) lies in the cell's north-west quarter: the sixteen run from two rows north and
  // two columns west of it, the bilinear four from one.
  r.at(row - 2, col - 2) = Raster::kNoData;
  EXPECT_DOUBLE_EQ(r.InterpolateCubic(4.9, 7.1), r.Interpolate(4.9, 7.1));
}

TEST(Raster, ResampledOutsideTheSourceIsNoData) {
  const Raster small = Plane([](double x, double) { return x; });
  Raster grid = small;
  grid.min_x_m += 100.0;
  EXPECT_TRUE(Raster::IsNoData(small.ResampledOnto(grid).at(5, 5)));
}

// What is refused before it is read: a raster of 20000 x 20000 cells (a sparse file of a few
// kilobytes; `diff` of it with itself grew to 18 GB) and one in feet, which every command
// would take for metres.
TEST(Raster, OversizeAndNonMetricRastersAreRefusedNamingTheFile) {
  testing::TempDir dir;
  GDALAllRegister();
  auto create = [&](const std::string& name, int size, int epsg) {
    char** options = CSLSetNameValue(nullptr, "TILED", "YES");
    options = CSLSetNameValue(options, "SPARSE_OK", "TRUE");
    GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
        (dir / name).c_str(), size, size, 1, GDT_Float32, options);
    CSLDestroy(options);
    double transform[6] = {500000.0, 1.0, 0.0, 5000000.0, 0.0, -1.0};
    ds->SetGeoTransform(transform);
    OGRSpatialReference srs;
    srs.importFromEPSG(epsg);
    ds->SetSpatialRef(&srs);
    GDALClose(ds);
  };
  create("huge.tif", 20000, 32632);
  EXPECT_LT(std::filesystem::file_size(dir / "huge.tif"), 10u << 20);
  const Result<Raster> huge = ReadGeoTiff(dir / "huge.tif");
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().find("huge.tif: 20000 x 20000 cells, more than"), std::string::npos)
      << huge.error();
  create("feet.tif", 10, 2229);  // NAD83 / California zone 5 (ftUS)
  const Result<Raster> feet = ReadGeoTiff(dir / "feet.tif");
  ASSERT_FALSE(feet);
  EXPECT_NE(feet.error().find("feet.tif: its CRS's unit is"), std::string::npos) << feet.error();
  EXPECT_NE(feet.error().find("not metres"), std::string::npos);
  create("utm.tif", 10, 32632);
  EXPECT_TRUE(ReadGeoTiff(dir / "utm.tif"));
}

}  // namespace
}  // namespace ts
