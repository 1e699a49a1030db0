#include "processing/change/dem_of_difference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "processing/change/change_json.h"
#include "processing/change/subsidence_regions.h"

namespace ts {
namespace {

// The raised-cosine bowl of the simulator, written out again here: depth D at the centre,
// zero from radius R; volume (1/2 - 2/pi^2) pi D R^2.
double Bowl(double x, double y, double cx, double cy, double depth, double radius) {
  const double r = std::hypot(x - cx, y - cy);
  return r >= radius ? 0.0 : depth * 0.5 * (1.0 + std::cos(std::numbers::pi * r / radius));
}

double BowlVolume(double depth, double radius) {
  return (0.5 - 2.0 / (std::numbers::pi * std::numbers::pi)) * std::numbers::pi * depth * radius *
         radius;
}

// A 60 m square at `cell` around the origin: a gentle plane, minus `lowering(x, y)`.
template <typename Fn>
Raster Surface(double cell, Fn lowering, double offset = 0.0) {
  const int n = static_cast<int>(std::lround(60.0 / cell));
  Raster r = Raster::Make(-30.0, 30.0, cell, n, n);
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const double x = r.CellCentreX(col), y = r.CellCentreY(row);
      r.at(row, col) = static_cast<float>(100.0 + 0.02 * x - 0.01 * y - lowering(x, y) + offset);
    }
  return r;
}

Raster Constant(const Raster& grid, float value) {
  Raster r = grid;
  std::fill(r.values.begin(), r.values.end(), value);
  return r;
}

DemEpoch Epoch(const std::string& name, const Raster& dem, std::optional<float> std_m) {
  DemEpoch e{name, dem, std::nullopt};
  if (std_m) e.std_dev = Constant(dem, *std_m);
  return e;
}

auto None = [](double, double) { return 0.0; };

TEST(DemOfDifference, BowlVolumeDepthAreaAndOneRegion) {
  const double depth = 0.5, radius = 7.0, cx = 9.5, cy = 6.5, s = 0.01;
  const Raster before = Surface(1.0, None);
  const Raster after =
      Surface(1.0, [&](double x, double y) { return Bowl(x, y, cx, cy, depth, radius); });
  const Result<ChangeResult> c =
      ComputeDemOfDifference(Epoch("before.tif", before, s), Epoch("after.tif", after, s));
  ASSERT_TRUE(c) << c.error();
  const double sigma = std::sqrt(2.0) * s, lod = 1.96 * sigma;
  EXPECT_EQ(c->cells_compared, 3600);
  EXPECT_FALSE(c->after_resampled);
  // Every cell whose lowering reaches the LoD, and no other.
  int cells = 0;
  double volume = 0.0;
  for (int r = 0; r < 60; ++r)
    for (int col = 0; col < 60; ++col) {
      const double d = Bowl(before.CellCentreX(col), before.CellCentreY(r), cx, cy, depth, radius);
      if (d >= lod) ++cells, volume += d;
    }
  EXPECT_EQ(c->lowering.cells, cells);
  EXPECT_NEAR(c->lowering.volume_m3, volume, 1e-3);
  // The rim below the LoD holds ~2 % of the bowl: close to the closed form, and under it.
  EXPECT_LT(c->lowering.volume_m3, BowlVolume(depth, radius));
  EXPECT_GT(c->lowering.volume_m3, 0.97 * BowlVolume(depth, radius));
  // Area: the disc where the cosine profile reaches the LoD.
  const double r_lod = radius / std::numbers::pi * std::acos(2.0 * lod / depth - 1.0);
  EXPECT_NEAR(c->lowering.area_m2, std::numbers::pi * r_lod * r_lod,
              0.05 * std::numbers::pi * r_lod * r_lod);
  EXPECT_NEAR(c->lowering.sigma_m3, sigma * std::sqrt(cells), 1e-5);
  EXPECT_NEAR(c->lowering.sigma_correlated_m3, sigma * cells, 1e-4);
  EXPECT_EQ(c->raising.cells, 0);
  EXPECT_NEAR(c->net_volume_m3, -volume, 1e-3);
  ASSERT_TRUE(c->max_subsidence_m);
  EXPECT_NEAR(*c->max_subsidence_m, depth, 1e-4);
  EXPECT_NEAR(c->max_subsidence_sigma_m, sigma, 1e-6);
  EXPECT_NEAR(c->max_subsidence_xy_m.x(), cx, 1e-9);
  EXPECT_NEAR(c->max_subsidence_xy_m.y(), cy, 1e-9);
  ASSERT_EQ(c->regions.size(), 1u);
  const SubsidenceRegion& region = c->regions[0];
  EXPECT_EQ(region.id, 1);
  EXPECT_EQ(region.significant_cells, cells);
  // Grown and extended into its basin, the region takes in the rim below the LoD: its volume
  // is the closed form's but for the last few mm of rim, where a ring's mean lowering is no
  // longer significant (sigma 14 mm per cell).
  EXPECT_GT(region.lowering.cells, cells + 8);
  EXPECT_GT(region.lowering.volume_m3, c->lowering.volume_m3);
  EXPECT_NEAR(region.lowering.volume_m3, BowlVolume(depth, radius),
              0.01 * BowlVolume(depth, radius));
  EXPECT_NEAR(region.centroid_xy_m.x(), cx, 0.05);
  EXPECT_NEAR(region.centroid_xy_m.y(), cy, 0.05);
  ASSERT_EQ(region.outline.size(), 1u);
  EXPECT_TRUE(region.outline[0].holes.empty());
  EXPECT_NEAR(c->stable_median_m, 0.0, 1e-5);
  EXPECT_TRUE(c->warnings.empty());
  // Every vertex of the outline is a cell corner, within the bowl's radius + a cell.
  for (const Eigen::Vector2d& p : region.outline[0].exterior) {
    EXPECT_NEAR(p.x(), std::round(p.x()), 1e-9);
    EXPECT_NEAR(p.y(), std::round(p.y()), 1e-9);
    EXPECT_LT(std::hypot(p.x() - cx, p.y() - cy), radius + 1.5);
  }
  EXPECT_EQ(region.outline[0].exterior.front(), region.outline[0].exterior.back());
}

// With noise of the size of a hills DEM's (0.05 m in the DoD), the region still holds the
// bowl's volume, within 10 % and within its own 2 sigma.
TEST(DemOfDifference, NoisyBowlRegionHoldsItsVolume) {
  const double depth = 0.5, radius = 7.0, s = 0.035;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, s);
  auto noisy = [&](Raster r) {
    for (float& v : r.values) v += static_cast<float>(noise(rng));
    return r;
  };
  const Raster before = noisy(Surface(1.0, None));
  const Raster after =
      noisy(Surface(1.0, [&](double x, double y) { return Bowl(x, y, 5, -12, depth, radius); }));
  const Result<ChangeResult> c =
      ComputeDemOfDifference(Epoch("b", before, s), Epoch("a", after, s));
  ASSERT_TRUE(c) << c.error();
  const double truth = BowlVolume(depth, radius);
  ASSERT_GE(c->regions.size(), 1u);
  EXPECT_NEAR(c->regions[0].lowering.volume_m3, truth, 0.1 * truth);
  EXPECT_NEAR(c->regions[0].lowering.volume_m3, truth, 2.0 * c->regions[0].lowering.sigma_m3);
  EXPECT_NEAR(c->regions[0].max_depth_m, depth, 2.0 * c->regions[0].max_depth_sigma_m + 0.05);
}

// Unchanged ground, both epochs with errors correlated over a few cells (as kriged DEMs'): per
// survey, dozens of cells pass the per-cell test by chance, often side by side. Listed as
// subsidence, such a cluster is reported in at most 5 % of the surveys, as t_critical's 95 %
// promises of one test; the per-cell cores alone would list one in most surveys.
TEST(DemOfDifference, UnchangedGroundListsNoRegionBeyondTheTestsLevel) {
  const double s = 0.01;
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  // White noise averaged over 3 x 3 cells, scaled back to `s` a cell.
  auto correlated = [&](Raster r) {
    const int n = r.rows;
    std::vector<double> white(static_cast<size_t>((n + 2) * (n + 2)));
    for (double& w : white) w = normal(rng);
    for (int row = 0; row < n; ++row)
      for (int col = 0; col < n; ++col) {
        double sum = 0.0;
        for (int dr = 0; dr < 3; ++dr)
          for (int dc = 0; dc < 3; ++dc) sum += white[(row + dr) * (n + 2) + col + dc];
        r.at(row, col) += static_cast<float>(s * sum / 3.0);
      }
    return r;
  };
  const int surveys = 200;
  int with_significant_cells = 0, with_a_core = 0, with_a_region = 0;
  for (int i = 0; i < surveys; ++i) {
    const Result<ChangeResult> c =
        ComputeDemOfDifference(Epoch("b", correlated(Surface(1.0, None)), s),
                               Epoch("a", correlated(Surface(1.0, None)), s));
    ASSERT_TRUE(c) << c.error();
    with_significant_cells += c->lowering.cells > 0;
    ChangeResult per_cell = *c;
    per_cell.region_deepest_t = 0.0;  // any core of min_region_area_m2 listed
    with_a_core += !FindSubsidenceRegions(per_cell, ChangeOptions{}).empty();
    with_a_region += !c->regions.empty();
  }
  EXPECT_EQ(with_significant_cells, surveys);
  EXPECT_GT(with_a_core, surveys / 2);
  EXPECT_LE(with_a_region, surveys / 20);
}

// The listing's boundary, on noise-free epochs of std 1 cm (sigma 14 mm): a 0.08 m bowl, its
// deepest cell 5.7 sigma down, is listed; a 0.04 m bowl, 2.8 sigma, is not (3600 cells: 4.35
// sigma), though its significant cells still count in the lowering.
TEST(DemOfDifference, AShallowBowlIsListedOnlyWhenItsDeepestCellStandsOutOfTheNoise) {
  const double s = 0.01;
  for (const auto& [depth, listed] : {std::pair{0.08, 1u}, std::pair{0.04, 0u}}) {
    const Result<ChangeResult> c = ComputeDemOfDifference(
        Epoch("b", Surface(1.0, None), s),
        Epoch("a", Surface(1.0, [&](double x, double y) { return Bowl(x, y, 9.5, 6.5, depth, 7); }),
              s));
    ASSERT_TRUE(c) << c.error();
    EXPECT_NEAR(c->region_deepest_t, 4.3456, 1e-3);
    EXPECT_GT(c->lowering.cells, 4) << depth;
    EXPECT_EQ(c->regions.size(), listed) << depth;
  }
}

// The outline of a 3 x 3 block is the square along its cell edges; a ring-shaped lowering has
// a hole; a one-cell speckle counts in the totals but is not listed as a region.
TEST(DemOfDifference, RegionOutlinesHolesAndSpeckles) {
  auto lowering = [](double x, double y) {
    if (x > 0 && x < 3 && y > 0 && y < 3) return 1.0;  // block of cells (0..3, 0..3)
    const double r = std::max(std::abs(x + 15), std::abs(y + 15));
    if (r > 1 && r < 3) return 0.8;  // a square annulus of 32 cells around (-15, -15)
    if (x > 20 && x < 21 && y > 20 && y < 21) return 0.5;  // one cell
    return 0.0;
  };
  const Result<ChangeResult> c = ComputeDemOfDifference(Epoch("b", Surface(1.0, None), 0.01f),
                                                        Epoch("a", Surface(1.0, lowering), 0.01f));
  ASSERT_TRUE(c) << c.error();
  EXPECT_EQ(c->lowering.cells, 9 + 32 + 1);
  EXPECT_NEAR(c->lowering.volume_m3, 9 * 1.0 + 32 * 0.8 + 0.5, 1e-3);
  ASSERT_EQ(c->regions.size(), 2u);
  // Largest volume first: the annulus (25.6 m3), then the block (9 m3).
  EXPECT_NEAR(c->regions[0].lowering.volume_m3, 25.6, 1e-3);
  EXPECT_EQ(c->regions[0].outline.at(0).holes.size(), 1u);
  EXPECT_NEAR(c->regions[1].lowering.area_m2, 9.0, 1e-9);
  const auto& square = c->regions[1].outline.at(0).exterior;
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const Eigen::Vector2d& p : square)
    min_x = std::min(min_x, p.x()), max_x = std::max(max_x, p.x()), min_y = std::min(min_y, p.y()),
    max_y = std::max(max_y, p.y());
  EXPECT_EQ(min_x, 0.0);
  EXPECT_EQ(max_x, 3.0);
  EXPECT_EQ(min_y, 0.0);
  EXPECT_EQ(max_y, 3.0);
  // GeoJSON: the annulus is a polygon with two rings, the block one with one.
  const nlohmann::json g = SubsidenceGeoJson(*c);
  ASSERT_EQ(g["features"].size(), 2u);
  EXPECT_EQ(g["features"][0]["geometry"]["type"], "Polygon");
  EXPECT_EQ(g["features"][0]["geometry"]["coordinates"].size(), 2u);
  EXPECT_EQ(g["features"][1]["geometry"]["coordinates"].size(), 1u);
  EXPECT_EQ(g["features"][1]["properties"]["id"], 2);
}

TEST(DemOfDifference, RaisingLoweringAndNetVolume) {
  auto change = [](double x, double y) {
    return Bowl(x, y, -10, 0, 0.6, 6) - Bowl(x, y, 12, 12, 0.3, 5);  // a pit and a mound
  };
  const Result<ChangeResult> c = ComputeDemOfDifference(Epoch("b", Surface(1.0, None), 0.005f),
                                                        Epoch("a", Surface(1.0, change), 0.005f));
  ASSERT_TRUE(c) << c.error();
  EXPECT_NEAR(c->lowering.volume_m3, BowlVolume(0.6, 6), 0.02 * BowlVolume(0.6, 6));
  EXPECT_NEAR(c->raising.volume_m3, BowlVolume(0.3, 5), 0.02 * BowlVolume(0.3, 5));
  EXPECT_NEAR(c->net_volume_m3, c->raising.volume_m3 - c->lowering.volume_m3, 1e-6);
  EXPECT_NEAR(c->net_sigma_m3, std::hypot(c->lowering.sigma_m3, c->raising.sigma_m3), 1e-9);
  EXPECT_NEAR(c->max_subsidence_xy_m.x(), -10.0, 0.6);  // a cell either side of the centre
  EXPECT_EQ(c->regions.size(), 1u);
}

// A fixed level of detection with no std grids; without either, one clear error.
TEST(DemOfDifference, FixedLevelOfDetectionAndMissingStd) {
  auto bowl = [](double x, double y) { return Bowl(x, y, 10, -10, 0.5, 7); };
  ChangeOptions o;
  o.lod_m = 0.1;
  const Result<ChangeResult> c = ComputeDemOfDifference(Epoch("b", Surface(1.0, None), {}),
                                                        Epoch("a", Surface(1.0, bowl), {}), o);
  ASSERT_TRUE(c) << c.error();
  EXPECT_TRUE(c->sigma_from_lod);
  int cells = 0;
  for (int r = 0; r < 60; ++r)
    for (int col = 0; col < 60; ++col)
      cells += bowl(c->dod.CellCentreX(col), c->dod.CellCentreY(r)) >= 0.1;
  EXPECT_EQ(c->lowering.cells, cells);
  EXPECT_NEAR(c->max_subsidence_sigma_m, 0.1 / 1.96, 1e-6);
  EXPECT_FALSE(c->warnings.empty());
  const Result<ChangeResult> refused = ComputeDemOfDifference(
      Epoch("before.tif", Surface(1.0, None), 0.01f), Epoch("after.tif", Surface(1.0, bowl), {}));
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("after.tif"), std::string::npos) << refused.error();
  EXPECT_NE(refused.error().find("level of detection"), std::string::npos);
  o.lod_m = -1.0;
  EXPECT_FALSE(ComputeDemOfDifference(Epoch("b", Surface(1.0, None), 0.01f),
                                      Epoch("a", Surface(1.0, None), 0.01f), o));
}

// The later DEM on a finer, shifted grid is resampled onto the earlier one.
TEST(DemOfDifference, ResamplesAnotherGrid) {
  const double depth = 0.5, radius = 7.0;
  Raster after =
      Surface(0.5, [&](double x, double y) { return Bowl(x, y, 9.5, 6.5, depth, radius); });
  after.min_x_m += 0.25;
  after.max_y_m -= 0.25;
  for (int r = 0; r < after.rows; ++r)  // re-sample the surface at the shifted centres
    for (int c = 0; c < after.cols; ++c) {
      const double x = after.CellCentreX(c), y = after.CellCentreY(r);
      after.at(r, c) =
          static_cast<float>(100.0 + 0.02 * x - 0.01 * y - Bowl(x, y, 9.5, 6.5, depth, radius));
    }
  const Result<ChangeResult> c =
      ComputeDemOfDifference(Epoch("b", Surface(1.0, None), 0.01f), Epoch("a", after, 0.01f));
  ASSERT_TRUE(c) << c.error();
  EXPECT_TRUE(c->after_resampled);
  EXPECT_EQ(c->dod.cols, 60);
  EXPECT_GT(c->cells_compared, 3400);  // the shifted grid leaves an edge row and column out
  EXPECT_NEAR(c->lowering.volume_m3, BowlVolume(depth, radius), 0.03 * BowlVolume(depth, radius));
  EXPECT_NEAR(*c->max_subsidence_m, depth, 0.01);
}

TEST(DemOfDifference, RefusesWhatCannotBeCompared) {
  const Raster here = Surface(1.0, None);
  Raster far = here;
  far.min_x_m += 1000.0;
  Result<ChangeResult> c =
      ComputeDemOfDifference(Epoch("here.tif", here, 0.01f), Epoch("far.tif", far, 0.01f));
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find("far.tif: does not overlap here.tif"), std::string::npos) << c.error();

  Raster holes = Constant(here, Raster::kNoData);
  c = ComputeDemOfDifference(Epoch("here.tif", here, 0.01f), Epoch("holes.tif", holes, 0.01f));
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find("no cell has data in both"), std::string::npos) << c.error();

  Raster utm = here;
  utm.crs_wkt = "EPSG:32633";
  c = ComputeDemOfDifference(Epoch("here.tif", here, 0.01f), Epoch("utm.tif", utm, 0.01f));
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find("utm.tif"), std::string::npos) << c.error();
  EXPECT_NE(c.error().find("station frame"), std::string::npos) << c.error();

  DemEpoch bad_std = Epoch("bad.tif", here, 0.01f);
  bad_std.std_dev = Raster::Make(0, 0, 1.0, 3, 3, 0.01f);
  c = ComputeDemOfDifference(Epoch("here.tif", here, 0.01f), bad_std);
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find("bad.tif: its standard deviation grid"), std::string::npos);
}

// Unchanged ground that differs by a constant between the epochs: a datum problem, warned.
TEST(DemOfDifference, WarnsOfAHeightDatumOffset) {
  const Result<ChangeResult> c = ComputeDemOfDifference(
      Epoch("b", Surface(1.0, None), 0.05f), Epoch("a", Surface(1.0, None, 0.08), 0.05f));
  ASSERT_TRUE(c) << c.error();
  EXPECT_EQ(c->raising.cells, 0);  // 0.08 m is below 1.96 * 0.071 m
  EXPECT_NEAR(c->stable_median_m, 0.08, 1e-4);
  ASSERT_EQ(c->warnings.size(), 1u);
  EXPECT_NE(c->warnings[0].find("datum"), std::string::npos);
  EXPECT_FALSE(c->max_subsidence_m);
  const nlohmann::json j = ChangeToJson(*c, ChangeOptions{});
  EXPECT_TRUE(j["max_subsidence"].is_null());
  EXPECT_EQ(j["schema"], "topostation.change");
  EXPECT_EQ(j["subsidence_regions"].size(), 0u);
}

// A later epoch 0.3 m high everywhere (a tripod height misread) with a real pit: levelled on
// the unchanged ground, the pit alone remains.
TEST(DemOfDifference, RemovesAStableGroundOffsetOnRequest) {
  auto pit = [](double x, double y) { return Bowl(x, y, -8.5, 10.5, 0.6, 5); };
  const DemEpoch before = Epoch("b", Surface(1.0, None), 0.02f);
  const DemEpoch after = Epoch("a", Surface(1.0, pit, 0.3), 0.02f);
  const Result<ChangeResult> raw = ComputeDemOfDifference(before, after);
  ASSERT_TRUE(raw) << raw.error();
  EXPECT_GT(raw->raising.cells, 3000);  // everything "rose"
  ChangeOptions o;
  o.remove_stable_offset = true;
  const Result<ChangeResult> c = ComputeDemOfDifference(before, after, o);
  ASSERT_TRUE(c) << c.error();
  EXPECT_NEAR(c->offset_removed_m, 0.3, 1e-4);
  EXPECT_EQ(c->raising.cells, 0);
  ASSERT_EQ(c->regions.size(), 1u);
  EXPECT_NEAR(c->regions[0].lowering.volume_m3, BowlVolume(0.6, 5), 0.02 * BowlVolume(0.6, 5));
  EXPECT_NEAR(*c->max_subsidence_m, 0.6, 0.01);
  EXPECT_NEAR(ChangeToJson(*c, o)["height_offset_removed_m"].get<double>(), 0.3, 1e-4);
}

}  // namespace
}  // namespace ts
