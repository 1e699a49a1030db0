// The lines of sight against a dike of known geometry: a camera 1.5 m above level ground
// (z = 0) sees the field 20-30 m out over a dike. Every line to a point at distance D passes
// over distance x at 1.5 (1 - x / D). A DEM that bridged the hollow behind the dike with 1 m of
// ground must come down below those lines, and only where they pass.
#include "processing/dem/free_space.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ts {
namespace {

constexpr double kEye = 1.5;

std::vector<SightLine> FieldLines(double range_sigma_m, double field_z = 0.0) {
  std::vector<SightLine> lines;
  for (double y = -2.0; y <= 2.0 + 1e-9; y += 0.25)
    for (double x = 20.0; x <= 30.0 + 1e-9; x += 0.25)
      lines.push_back({{0.0, 0.0, kEye}, {x, y, field_z}, range_sigma_m});
  return lines;
}

// x 0..40 m, y -10..10 m, 1 m cells, all at `height`.
Raster Level(double height) {
  Raster dem = Raster::Make(0.0, 10.0, 1.0, 40, 20);
  for (float& v : dem.values) v = static_cast<float>(height);
  return dem;
}

TEST(FreeSpace, TheCeilingOfACellIsTheLowestLineOverIt) {
  const Raster grid = Level(0.0);
  const SightLineCeilings c = FindSightLineCeilings(FieldLines(0.0), grid, {});
  // On the line y = 0, over x: the lowest line is the one to the nearest point past the cell
  // and at least a cell beyond it (20 m: the line's end stops a cell short), at the cell's far
  // edge, where the lines are taken.
  for (int col = 1; col < 18; ++col) {
    const float ceiling = c.per_cell.at(10, col);  // row 10: y in [-1, 0)
    ASSERT_FALSE(Raster::IsNoData(ceiling)) << col;
    const double x_far = col + 1.0;
    EXPECT_NEAR(ceiling, kEye * (1.0 - x_far / 20.0), 1e-5) << col;
  }
  // No line reaches y = 8.
  EXPECT_TRUE(Raster::IsNoData(c.per_cell.at(2, 10)));
}

// Over the hollow, the lowest line lands on the first of the field seen past it: the ground
// there is the lowest the hidden ground plausibly is (ground_room.h).
TEST(FreeSpace, TheLowestLineOverACellLandsOnTheFieldPastIt) {
  const SightLineCeilings c = FindSightLineCeilings(FieldLines(0.0, -0.7), Level(0.0), {});
  int landed = 0;
  for (int r = 0; r < c.per_cell.rows; ++r)
    for (int col = 0; col < c.per_cell.cols; ++col) {
      const bool line = !Raster::IsNoData(c.per_cell.at(r, col));
      ASSERT_EQ(line, !Raster::IsNoData(c.landing_per_cell.at(r, col))) << r << " " << col;
      if (!line) continue;
      EXPECT_FLOAT_EQ(c.landing_per_cell.at(r, col), -0.7f);
      ++landed;
    }
  EXPECT_GT(landed, 2 * 28);  // the rows either side of y = 0, all the 28 m of the lines
}

TEST(FreeSpace, ALineStopsItsRangeSigmasShortOfItsPoint) {
  const Raster grid = Level(0.0);
  FreeSpaceOptions o;
  o.end_sigmas = 2.0;
  // A range sigma of 2.5 m: no line reaches within 5 m of its point. Nothing past 25 m (the
  // farthest point is 30 m out), and over 16-17 m only the lines to points 21 m out or more.
  const SightLineCeilings c = FindSightLineCeilings(FieldLines(2.5), grid, o);
  for (int col = 26; col < 40; ++col) EXPECT_TRUE(Raster::IsNoData(c.per_cell.at(10, col))) << col;
  EXPECT_NEAR(c.per_cell.at(10, 16), kEye * (1.0 - 17.0 / 22.0), 0.1);
}

TEST(FreeSpace, ABridgedHollowComesDownBelowEveryLineAndNothingElseMoves) {
  Raster dem = Level(0.0);
  // The bridge: 1 m of ground over the hollow 8-14 m out, across the whole width.
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 8; c < 14; ++c) dem.at(r, c) = 1.0f;
  const SightLineCeilings ceilings = FindSightLineCeilings(FieldLines(0.05), dem, {});
  const FreeSpaceResult result = LowerBelowSightLines(ceilings, {}, &dem);
  EXPECT_GT(result.cells_lowered, 0);
  // Below every ceiling where the bilinear surface is defined.
  for (const SightLineCeilings::Ceiling& e : ceilings.ceilings) {
    const double z = dem.Interpolate(e.x, e.y);
    if (std::isfinite(z)) {
      EXPECT_LE(z, e.height + 1e-3) << e.x << " " << e.y;
    }
  }
  // Over the hollow on the lines (|y| < 1.5), the bridge is cut to the lines' height; far
  // from them (|y| > 4) it stands; level ground never rises.
  EXPECT_LT(dem.at(10, 12), 1.5 * (1.0 - 12.0 / 20.0) + 0.05);
  EXPECT_FLOAT_EQ(dem.at(2, 10), 1.0f);
  EXPECT_FLOAT_EQ(dem.at(17, 10), 1.0f);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      if (c < 8 || c >= 14) {
        EXPECT_LE(dem.at(r, c), 0.0f);
      }
  // Cut only: nothing was raised and level ground under the lines is untouched.
  EXPECT_FLOAT_EQ(dem.at(10, 25), 0.0f);
}

// On the outermost half cell of the grid the surface is the nearest cell's (Raster::Interpolate,
// which the DEM's users read it with): a line over it brings that cell down, not a blend of it
// and its neighbour along the edge (foot seed 1: 27 edge cells stood 0.1-0.4 m above lines to
// the ground just past the square).
TEST(FreeSpace, OnTheOutermostHalfCellTheNearestCellComesDown) {
  Raster dem = Raster::Make(0.0, 3.0, 1.0, 3, 3);  // centres at 0.5, 1.5, 2.5
  for (float& v : dem.values) v = 0.0f;
  dem.at(0, 0) = 1.0f;
  SightLineCeilings c;
  c.ceilings.push_back({0.9, 2.9, 0.5, 0.0});  // above row 0's centres, nearest column 0
  LowerBelowSightLines(c, {}, &dem);
  EXPECT_LE(dem.Interpolate(0.9, 2.9), 0.5 + 1e-6);
  EXPECT_NEAR(dem.at(0, 0), 0.5, 1e-6);
  EXPECT_EQ(dem.at(0, 1), 0.0f);
}

// The most a line anywhere along the stretch that counts (a cell short of its point) passes
// under the DEM's surface, sampled every centimetre.
double MostUnderTheSurface(const std::vector<SightLine>& lines, const Raster& dem) {
  double most = 0.0;
  for (const SightLine& l : lines) {
    const Eigen::Vector3d d = l.point - l.camera;
    const double run = d.head<2>().norm();
    for (double s = 0.0; s < run - dem.cell_m; s += 0.01) {
      const Eigen::Vector3d q = l.camera + d * (s / run);
      const double surface = dem.Interpolate(q.x(), q.y());
      if (std::isfinite(surface)) most = std::max(most, surface - q.z());
    }
  }
  return most;
}

// Rough ground with a spike among low cells (a kriged blunder, terraces seed 2: a cell 3.9 m
// above its neighbours), lines to points 0.3 m under it, every half metre. The lowest line
// over a square need not be the one that binds: within a square the surface rises steeply to
// the spike, and a higher line passes under it there (0.5 m on terraces seed 2). Nor does a
// line pass lowest over a square, or nearest the surface, at points half a square apart, but
// at the square's edges. And a projection moves cells unevenly: the line that bound a square
// over the kriged DEM need not over the lowered one. With only the lowest line, taken every
// half square, in one pass, a line stays 0.11 m under the surface here; none may by a
// millimetre anywhere along it (the surface's curvature over a quarter-metre square could hide
// some, but does not here).
TEST(FreeSpace, NoLinePassesUnderTheLoweredSurfaceAnywhereAlongIt) {
  Raster dem = Raster::Make(0.0, 10.0, 1.0, 30, 20);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> rough(0.0f, 2.0f);
  for (float& v : dem.values) v = rough(random);
  dem.at(10, 12) = 6.0f;
  std::vector<SightLine> lines;
  for (double y = -9.375; y < 10.0; y += 0.5)
    for (double x = 2.125; x < 30.0; x += 0.5)
      lines.push_back({{-2.0, 0.3, 3.0}, {x, y, dem.Interpolate(x, y) - 0.3}, 0.0});
  const double before = MostUnderTheSurface(lines, dem);
  LowerBelowSightLines(FindSightLineCeilings(lines, dem, {}), {}, &dem);
  EXPECT_GT(before, 1.0);
  EXPECT_LT(MostUnderTheSurface(lines, dem), 1e-3);
}

// A cell brought down was kriged from points that stood above a line some other point proved
// clear: they were wrong by at least the lowering, and the ground may lie anywhere below the
// line. Its std spans the lowering, in quadrature with its own, as a cell lowered to the horizon
// does (horizon_limit.h); a cell the lines left alone keeps its std.
TEST(FreeSpace, ALoweredCellsStdSpansItsLowering) {
  Raster dem = Raster::Make(0.0, 3.0, 1.0, 3, 3);
  for (float& v : dem.values) v = 0.0f;
  dem.at(0, 0) = 1.0f;
  Raster std_dev = dem;
  for (float& v : std_dev.values) v = 0.03f;
  SightLineCeilings c;
  c.ceilings.push_back({0.9, 2.9, 0.5, 0.0});
  LowerBelowSightLines(c, {}, &dem, &std_dev);
  EXPECT_NEAR(std_dev.at(0, 0), std::hypot(0.03, 0.5), 1e-6);
  EXPECT_FLOAT_EQ(std_dev.at(0, 1), 0.03f);
  EXPECT_FLOAT_EQ(std_dev.at(2, 2), 0.03f);
}

// A riser's face beside a lower tread (terraces seed 2): ground bridged 8-14 m out that rises
// 3 m per metre across the lines, and one camera's lines to two points of one quarter-metre
// square 20 m out, 0.24 m apart across them. The line that rises least passes over the low side
// of the bridge; the other, over its high side, passed under the surface there by 0.13-0.19 m
// while only the first was walked. Every line is: neither may pass under the lowered surface.
TEST(FreeSpace, EveryLineToOneSmallSquareBindsWhereTheGroundSlopesAcrossThem) {
  Raster dem = Level(0.0);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 8; c < 14; ++c)
      dem.at(r, c) = static_cast<float>(std::max(0.0, 1.0 + 3.0 * dem.CellCentreY(r)));
  const std::vector<SightLine> lines = {{{0.0, 0.0, kEye}, {20.0, 0.01, 0.0}, 0.0},
                                        {{0.0, 0.0, kEye}, {20.2, 0.24, 0.2}, 0.0}};
  ASSERT_GT(MostUnderTheSurface({lines[1]}, dem), 0.5);
  LowerBelowSightLines(FindSightLineCeilings(lines, dem, {}), {}, &dem);
  EXPECT_LT(MostUnderTheSurface(lines, dem), 1e-3);
}

// Ground seen as points, four per quarter-metre square across y -2..2 with a height sigma of
// 2 cm: level (z = 0) out to 10 m, a hump 0.5 m high 10-14 m out, the field 20-30 m out that
// a camera 1.5 m up sees over it (the line to 20 m is 0.6 m high over 12 m). The ground just
// behind the hump is hidden.
std::vector<Eigen::Vector3d> SeenOverAHump() {
  std::vector<Eigen::Vector3d> ground;
  for (double y = -1.9375; y < 2.0; y += 0.125)
    for (double x = 1.0625; x < 30.0; x += 0.125) {
      if (x >= 14.0 && x < 20.0) continue;
      ground.emplace_back(x, y, x >= 10.0 && x < 14.0 ? 0.5 : 0.0);
    }
  return ground;
}

std::vector<SightLine> LinesTo(const std::vector<Eigen::Vector3d>& points) {
  std::vector<SightLine> lines;
  for (const Eigen::Vector3d& p : points) lines.push_back({{0.0, 0.0, kEye}, p, 0.02});
  return lines;
}

// A point matched 40 m out and 5 m down: its line passes under the hump by 1.2-1.5 m (and
// under the level ground before it), which the cameras saw. A point of the hidden ground just
// behind the hump is as impossible to see. The lines to the ground seen, and to the field 45 m
// out past it, pass over.
TEST(FreeSpace, ALineUnderGroundThatOtherPointsSawWentThroughIt) {
  const std::vector<Eigen::Vector3d> ground = SeenOverAHump();
  std::vector<Eigen::Vector3d> points = ground;
  points.emplace_back(40.0, 0.1, -5.0);  // behind the hill
  points.emplace_back(16.0, 0.1, -0.3);  // hidden behind the hump
  points.emplace_back(45.0, 0.1, 0.0);   // the field seen farther
  const std::vector<double> variances(ground.size(), 0.02 * 0.02);
  const std::vector<uint8_t> through =
      FindLinesThroughSeenGround(LinesTo(points), ground, variances, 1.0, {});
  ASSERT_EQ(through.size(), points.size());
  for (size_t i = 0; i < ground.size(); ++i) ASSERT_EQ(through[i], 0) << ground[i].transpose();
  EXPECT_EQ(through[ground.size()], 1);
  EXPECT_EQ(through[ground.size() + 1], 1);
  EXPECT_EQ(through[ground.size() + 2], 0);
  FreeSpaceOptions off;
  off.enabled = false;
  for (uint8_t t : FindLinesThroughSeenGround(LinesTo(points), ground, variances, 1.0, off))
    EXPECT_EQ(t, 0);
  EXPECT_THROW(FindLinesThroughSeenGround(LinesTo(points), ground, {0.1}, 1.0, {}),
               std::invalid_argument);
}

// Over level seen ground, a line may pass under a square's second lowest point by its diagonal
// (ground as steep as 45 degrees in the square) and 3 of its sigmas: a point matched 0.3 m low
// at 30 m is kept (its line is 0.18 m under the ground 2 m before it), one 2 m low is not.
// One point alone in a square, or one square, is no witness: a blunder floating 3 m up over
// 12 m does not refute the lines under it; four points there, one square, do not either,
// unless one square is asked for.
TEST(FreeSpace, WhatWitnessesALineThroughSeenGround) {
  std::vector<Eigen::Vector3d> level;
  for (double y = -1.9375; y < 2.0; y += 0.125)
    for (double x = 1.0625; x < 30.0; x += 0.125) level.emplace_back(x, y, 0.0);
  const std::vector<double> variances(level.size(), 0.02 * 0.02);
  const std::vector<SightLine> low = LinesTo({{30.0, 0.1, -0.3}, {30.0, 0.1, -2.0}});
  const std::vector<uint8_t> judged = FindLinesThroughSeenGround(low, level, variances, 1.0, {});
  EXPECT_EQ(judged[0], 0);
  EXPECT_EQ(judged[1], 1);

  const std::vector<SightLine> under = LinesTo({{30.0, 0.05, 0.0}});
  std::vector<Eigen::Vector3d> floating = {{12.05, 0.05, 3.0}};
  EXPECT_EQ(FindLinesThroughSeenGround(under, floating, {}, 1.0, {})[0], 0);
  for (double dx : {0.05, 0.1, 0.15}) floating.emplace_back(12.0 + dx, 0.02, 3.0);
  EXPECT_EQ(FindLinesThroughSeenGround(under, floating, {}, 1.0, {})[0], 0);
  FreeSpaceOptions one;
  one.seen_ground_witnesses = 1;
  EXPECT_EQ(FindLinesThroughSeenGround(under, floating, {}, 1.0, one)[0], 1);
}

TEST(FreeSpace, NoDataCellsStayNoData) {
  Raster dem = Level(1.0);
  dem.at(10, 10) = Raster::kNoData;
  const SightLineCeilings ceilings = FindSightLineCeilings(FieldLines(0.05), dem, {});
  LowerBelowSightLines(ceilings, {}, &dem);
  EXPECT_TRUE(Raster::IsNoData(dem.at(10, 10)));
}

}  // namespace
}  // namespace ts
