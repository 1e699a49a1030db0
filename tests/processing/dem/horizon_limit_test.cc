// LimitToHorizon against a brow of known geometry: a viewpoint 1.5 m up sees ground rising at
// 10 % out to a brow 10 m away (1.0 m high); the line of sight over the brow falls at 5 %, so
// hidden ground at distance d lies below 1.5 - 0.05 d. The DEM given carries the rise on
// (0.1 d), as kriging's drift would. The object shadows: level ground seen out to 10 m and a bush
// 1 m high just beyond it, whose top's line of sight falls at 5 %: the ground behind it, up to
// 1.5 - 0.05 d, is hidden by the bush.
#include "processing/dem/horizon_limit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace ts {
namespace {

struct HorizonScene {
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> ground;
  void Ring(double from_m, double to_m, bool is_ground,
            const std::function<double(double)>& height) {
    for (double az = -30.0; az <= 30.0; az += 0.25)
      for (double d = from_m; d <= to_m + 1e-9; d += 0.25) {
        const double a = az * M_PI / 180.0;
        points.emplace_back(d * std::cos(a), d * std::sin(a), height(d));
        ground.push_back(is_ground);
      }
  }
};

double Rise(double d) { return 0.1 * d; }

// x 0..20 m, y -5..5 m, every cell 0.1 d.
Raster Extrapolated() {
  Raster dem = Raster::Make(0.0, 5.0, 1.0, 20, 10);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      dem.at(r, c) = static_cast<float>(Rise(std::hypot(dem.CellCentreX(c), dem.CellCentreY(r))));
  return dem;
}

const Eigen::Vector3d kStationEye(0.0, 0.0, 1.5);

// The hidden cells 12-16 m out (0.1 d above the horizon by over 0.2 m, within edge_m of the
// seen ground: kriging's reach) lowered to the line of sight over the brow, 1.5 - 0.05 d;
// how many there are.
int ExpectHollowLoweredToTheLineOfSight(const Raster& dem) {
  int lowered = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double d = std::hypot(dem.CellCentreX(c), dem.CellCentreY(r));
      if (d > 12.0 && d < 16.0) {
        EXPECT_NEAR(dem.at(r, c), 1.5 - 0.05 * d, 1e-4) << "hidden, at " << d << " m";
        ++lowered;
      }
    }
  return lowered;
}

TEST(HorizonLimit, LowersTheHollowBehindABrowToTheLineOfSight) {
  HorizonScene s;
  s.Ring(2.0, 10.0, true, Rise);
  Raster dem = Extrapolated();
  const HorizonLimitResult result = LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double d = std::hypot(dem.CellCentreX(c), dem.CellCentreY(r));
      if (d < 10.0) {
        EXPECT_FLOAT_EQ(dem.at(r, c), Rise(d)) << "seen, at " << d << " m";
      }
    }
  const int lowered = ExpectHollowLoweredToTheLineOfSight(dem);
  EXPECT_GT(lowered, 20);
  EXPECT_GE(result.cells_lowered, lowered);
  EXPECT_GT(result.mean_lowering_m, 0.3);
}

// The lowering rests on "seen ground is matched ground": the kriged height stays possible
// (ground seen and not matched), so a lowered cell's std spans the lowering, in quadrature with
// its own; a cell left alone keeps its std.
TEST(HorizonLimit, ALoweredCellsStdSpansTheHeightItWasLoweredFrom) {
  HorizonScene s;
  s.Ring(2.0, 10.0, true, Rise);
  Raster dem = Extrapolated();
  const Raster kriged = dem;
  Raster std = dem;
  for (float& v : std.values) v = 0.1f;
  LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem, &std);
  ASSERT_GT(ExpectHollowLoweredToTheLineOfSight(dem), 20);
  for (size_t i = 0; i < dem.values.size(); ++i) {
    const double lowering = kriged.values[i] - dem.values[i];
    EXPECT_NEAR(std.values[i], std::hypot(0.1, lowering), 1e-5) << i;
  }
}

// The brow's own crest is convex ground a morphological filter takes for an object (a dike's
// or an embankment's top): the points on it stand on the terrain, not above it, and still set
// the horizon the hollow behind lies below.
TEST(HorizonLimit, ABrowLeftOutByTheGroundFilterStillHidesTheHollow) {
  HorizonScene s;
  s.Ring(2.0, 9.0, true, Rise);
  s.Ring(9.25, 10.0, false, Rise);
  Raster dem = Extrapolated();
  const HorizonLimitResult result = LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem);
  const int lowered = ExpectHollowLoweredToTheLineOfSight(dem);
  EXPECT_GT(lowered, 20);
  EXPECT_GE(result.cells_lowered, lowered);
}

// An embankment's top at eye level, seen only here and there: a few points on the crest, and
// nothing within edge_m of the hollow behind but them. One or two directions to seen ground are
// on one side of a cell by definition: it lies beyond the edge all the same.
TEST(HorizonLimit, AFewPointsOnTheBrowStillHideTheHollow) {
  HorizonScene s;
  s.Ring(2.0, 6.0, true, Rise);
  for (double az = -3.0; az <= 3.0; az += 0.25)
    for (const double d : {9.75, 10.0}) {
      const double a = az * M_PI / 180.0;
      s.points.emplace_back(d * std::cos(a), d * std::sin(a), Rise(d));
      s.ground.push_back(1);
    }
  Raster dem = Extrapolated();
  LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem);
  for (const double x : {14.5, 15.5})
    for (const double y : {-0.5, 0.5}) {
      int row = 0, col = 0;
      ASSERT_TRUE(dem.CellOf(x, y, &row, &col));
      EXPECT_NEAR(dem.at(row, col), 1.5 - 0.05 * std::hypot(x, y), 1e-4) << x << " " << y;
    }
}

// Ground seen beyond the hollow, well above the line over the brow: what lies between was in
// view and went unmatched, not hidden. The lowest line of sight to that farther ground passed
// over the cells and bounds them, not the brow's horizon.
TEST(HorizonLimit, GroundSeenBeyondBoundsTheCellsByTheLineToIt) {
  HorizonScene s;
  s.Ring(2.0, 10.0, true, Rise);
  s.Ring(25.0, 30.0, true, [](double) { return 0.5; });  // 1.0 below the eye: lowest at 25 m
  Raster dem = Extrapolated();
  LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem);
  int bounded = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double d = std::hypot(dem.CellCentreX(c), dem.CellCentreY(r));
      const double line = 1.5 - d / 25.0;
      if (d < 12.0 || d > 16.0) continue;
      if (Rise(d) > line + 0.2) {
        EXPECT_NEAR(dem.at(r, c), line, 1e-4) << d << " m: the line over it, not the horizon";
        ++bounded;
      } else {
        EXPECT_FLOAT_EQ(dem.at(r, c), Rise(d)) << d << " m: below the line, left alone";
      }
    }
  EXPECT_GT(bounded, 5);
}

TEST(HorizonLimit, LeavesGroundBetweenSeenGroundAndBehindObjects) {
  HorizonScene between;  // the far side of the hollow is seen too: the hollow is interpolated
  between.Ring(2.0, 10.0, true, Rise);
  between.Ring(18.0, 22.0, true, [](double) { return 1.6; });
  Raster dem = Extrapolated();
  EXPECT_EQ(LimitToHorizon(between.points, between.ground, kStationEye, {}, &dem).cells_lowered, 0);
  EXPECT_EQ(dem.values, Extrapolated().values);

  HorizonScene tree;  // a canopy over the brow sets the horizon: the ground behind may rise
  tree.Ring(2.0, 10.0, true, Rise);
  tree.Ring(9.5, 9.5, false, [](double) { return 3.0; });
  EXPECT_EQ(LimitToHorizon(tree.points, tree.ground, kStationEye, {}, &dem).cells_lowered, 0);

  HorizonScene brow;
  brow.Ring(2.0, 10.0, true, Rise);
  HorizonLimitOptions off;
  off.enabled = false;
  EXPECT_EQ(LimitToHorizon(brow.points, brow.ground, kStationEye, off, &dem).cells_lowered, 0);
  EXPECT_EQ(dem.values, Extrapolated().values);
}

double FlatGround(double) { return 0.0; }

// Level ground seen from 2 to 10 m and, unless bush_height_m is 0, a bush from 10 to 10.5 m.
HorizonScene BushBehindLevelGround(double bush_height_m) {
  HorizonScene s;
  s.Ring(2.0, 10.0, true, FlatGround);
  if (bush_height_m > 0.0) s.Ring(10.25, 10.5, false, [&](double) { return bush_height_m; });
  return s;
}

// x 0..20 m, y -5..5 m: the level ground carried on (kriging's reach), beyond 12 m at
// height_m; std 0.1 + 0.05 d.
void LevelDem(double height_m, Raster* dem, Raster* std) {
  *dem = Raster::Make(0.0, 5.0, 1.0, 20, 10);
  *std = *dem;
  for (int r = 0; r < dem->rows; ++r)
    for (int c = 0; c < dem->cols; ++c) {
      const double d = std::hypot(dem->CellCentreX(c), dem->CellCentreY(r));
      dem->at(r, c) = static_cast<float>(d <= 12.0 ? 0.0 : height_m);
      std->at(r, c) = static_cast<float>(0.1 + 0.05 * d);
    }
}

// Distance of a cell centre from the seen ground (the ring 2-10 m, within +-30 degrees).
double FromSeenGround(double x, double y) { return std::max(0.0, std::hypot(x, y) - 10.0); }

TEST(HorizonLimit, KeepsGroundInAnObjectsShadowUpToItsReach) {
  const HorizonScene s = BushBehindLevelGround(1.0);
  Raster dem, std;
  LevelDem(0.0, &dem, &std);
  const Raster given = dem;
  HorizonLimitOptions o;  // reach 7 m behind objects
  const double data_reach = 5.5;
  const HorizonLimitResult result =
      LimitToHorizon(s.points, s.ground, kStationEye, o, &dem, &std, data_reach);
  int kept = 0, dropped = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double gap = FromSeenGround(dem.CellCentreX(c), dem.CellCentreY(r));
      if (gap <= data_reach - 0.3 || (gap > data_reach + 0.3 && gap <= 6.7)) {
        EXPECT_EQ(dem.at(r, c), given.at(r, c)) << "at " << gap << " m from ground";
        EXPECT_FALSE(Raster::IsNoData(std.at(r, c)));
        kept += gap > data_reach + 0.3;
      } else if (gap > 7.3) {
        EXPECT_TRUE(Raster::IsNoData(dem.at(r, c))) << "beyond the shadow's reach, " << gap;
        EXPECT_TRUE(Raster::IsNoData(std.at(r, c)));
        ++dropped;
      }
    }
  EXPECT_GT(kept, 5);
  EXPECT_GT(dropped, 5);
  EXPECT_GE(result.cells_in_object_shadows, kept);
  EXPECT_GE(result.cells_unexplained, dropped);
  EXPECT_EQ(result.cells_lowered, 0);  // the bush, not the ground, sets the horizon
}

TEST(HorizonLimit, DropsFarCellsThatNoObjectHides) {
  const double data_reach = 5.5;
  auto far_cells_kept = [&](const HorizonScene& s, double height_behind_m) {
    Raster dem, std;
    LevelDem(height_behind_m, &dem, &std);
    LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem, &std, data_reach);
    int kept = 0;
    for (int r = 0; r < dem.rows; ++r)
      for (int c = 0; c < dem.cols; ++c) {
        const bool far = FromSeenGround(dem.CellCentreX(c), dem.CellCentreY(r)) > data_reach + 0.3;
        if (!far) continue;
        EXPECT_EQ(Raster::IsNoData(dem.at(r, c)), Raster::IsNoData(std.at(r, c)));
        kept += !Raster::IsNoData(dem.at(r, c));
      }
    return kept;
  };
  EXPECT_GT(far_cells_kept(BushBehindLevelGround(1.0), 0.0), 5);  // as above
  // Nothing stands there: the ground just was not seen.
  EXPECT_EQ(far_cells_kept(BushBehindLevelGround(0.0), 0.0), 0);
  // Too low to be an object: terrain the ground filter left out.
  EXPECT_EQ(far_cells_kept(BushBehindLevelGround(0.3), 0.0), 0);
  // Ground behind the bush standing above its line of sight would have been seen.
  EXPECT_EQ(far_cells_kept(BushBehindLevelGround(1.0), 1.2), 0);
  // A bush on a brow, over a hollow that the brow hides as well: the hollow is not the bush's.
  HorizonScene brow_bush;
  brow_bush.Ring(2.0, 10.0, true, Rise);
  brow_bush.Ring(10.25, 10.5, false, [](double) { return 2.0; });
  Raster hollow = Extrapolated(), hollow_std = Extrapolated();
  for (int r = 0; r < hollow.rows; ++r)
    for (int c = 0; c < hollow.cols; ++c) {
      const double d = std::hypot(hollow.CellCentreX(c), hollow.CellCentreY(r));
      if (d > 12.0) hollow.at(r, c) = static_cast<float>(1.5 - 0.05 * d - 0.5);
    }
  const HorizonLimitResult behind_brow = LimitToHorizon(
      brow_bush.points, brow_bush.ground, kStationEye, {}, &hollow, &hollow_std, data_reach);
  EXPECT_EQ(behind_brow.cells_in_object_shadows, 0);
  EXPECT_GT(behind_brow.cells_unexplained, 5);
  // Switched off: no cell beyond kriging's reach.
  HorizonLimitOptions none;
  none.object_shadow_reach_m = 0.0;
  const HorizonScene bush = BushBehindLevelGround(1.0);
  Raster dem, std;
  LevelDem(0.0, &dem, &std);
  EXPECT_EQ(LimitToHorizon(bush.points, bush.ground, kStationEye, none, &dem, &std, data_reach)
                .cells_in_object_shadows,
            0);
}

// The cells left without a value beyond kriging's reach behind the brow get the line of sight
// over it as their horizon, 1.5 - 0.05 d, for the terrain correction's estimate of them; cells
// with a value get none. Behind a bush the bush sets the horizon, and the ground behind it may
// rise above it: no horizon there.
TEST(HorizonLimit, GivesTheCellsLeftWithoutAValueTheHorizonOverThem) {
  HorizonScene s;
  s.Ring(2.0, 10.0, true, Rise);
  Raster dem = Extrapolated(), std = Extrapolated();
  const HorizonLimitResult result =
      LimitToHorizon(s.points, s.ground, kStationEye, {}, &dem, &std, 5.5);
  ASSERT_EQ(result.horizon.values.size(), dem.values.size());
  int bounded = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double x = dem.CellCentreX(c), y = dem.CellCentreY(r), d = std::hypot(x, y);
      const bool in_view = std::abs(std::atan2(y, x)) < 29.0 * M_PI / 180.0;
      if (!Raster::IsNoData(dem.at(r, c))) {
        EXPECT_TRUE(Raster::IsNoData(result.horizon.at(r, c))) << "has a value, at " << d << " m";
      } else if (in_view) {
        EXPECT_NEAR(result.horizon.at(r, c), 1.5 - 0.05 * d, 1e-4) << "at " << d << " m";
        ++bounded;
      }
    }
  EXPECT_GT(bounded, 5);

  const HorizonScene bush = BushBehindLevelGround(1.0);
  Raster level, level_std;
  LevelDem(0.0, &level, &level_std);
  const HorizonLimitResult behind_bush =
      LimitToHorizon(bush.points, bush.ground, kStationEye, {}, &level, &level_std, 5.5);
  int without = 0;
  for (size_t i = 0; i < level.values.size(); ++i)
    if (Raster::IsNoData(level.values[i])) {
      const float h = behind_bush.horizon.values[i];
      EXPECT_TRUE(Raster::IsNoData(h)) << h;
      ++without;
    }
  EXPECT_GT(without, 5);
}

TEST(HorizonLimit, RejectsBadInput) {
  Raster dem = Extrapolated();
  HorizonLimitOptions bad;
  bad.edge_m = 0.5;
  std::string why;
  EXPECT_FALSE(bad.Check(&why));
  EXPECT_NE(why.find("edge_m"), std::string::npos);
  EXPECT_THROW(LimitToHorizon({}, {}, kStationEye, bad, &dem), std::invalid_argument);
  EXPECT_THROW(LimitToHorizon({{1, 0, 0}}, {}, kStationEye, {}, &dem), std::invalid_argument);
  Raster other_grid = Raster::Make(0.0, 5.0, 1.0, 10, 10);
  EXPECT_THROW(LimitToHorizon({}, {}, kStationEye, {}, &dem, &other_grid), std::invalid_argument);
  HorizonLimitOptions bad_reach;
  bad_reach.object_shadow_reach_m = -1.0;
  EXPECT_FALSE(bad_reach.Check(&why));
  EXPECT_NE(why.find("object_shadow_reach_m"), std::string::npos);
  HorizonLimitOptions bad_height;
  bad_height.min_object_height_m = 0.0;
  EXPECT_FALSE(bad_height.Check(&why));
  EXPECT_NE(why.find("min_object_height_m"), std::string::npos);
}

}  // namespace
}  // namespace ts
