// LimitToHorizon against a brow of known geometry: a viewpoint 1.5 m up sees ground rising at
// 10 % out to a brow 10 m away (1.0 m high); the line of sight over the brow falls at 5 %, so
// hidden ground at distance d lies below 1.5 - 0.05 d. The DEM given carries the rise on
// (0.1 d), as kriging's drift would.
#include "processing/dem/horizon_limit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ts {
namespace {

struct Scene {
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> ground;
  void Ring(double from_m, double to_m, bool is_ground, double (*height)(double)) {
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

const Eigen::Vector3d kViewpoint(0.0, 0.0, 1.5);

TEST(HorizonLimit, LowersTheHollowBehindABrowToTheLineOfSight) {
  Scene s;
  s.Ring(2.0, 10.0, true, Rise);
  Raster dem = Extrapolated();
  const HorizonLimitResult result = LimitToHorizon(s.points, s.ground, kViewpoint, {}, &dem);
  int lowered = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double d = std::hypot(dem.CellCentreX(c), dem.CellCentreY(r));
      const double z = dem.at(r, c);
      if (d < 10.0) {
        EXPECT_FLOAT_EQ(z, Rise(d)) << "seen, at " << d << " m";
      } else if (d > 12.0 && d < 16.0) {  // hidden, 0.1 d above the horizon by over 0.2 m, and
                                          // within edge_m of the seen ground (kriging's reach)
        EXPECT_NEAR(z, 1.5 - 0.05 * d, 1e-4) << "hidden, at " << d << " m";
        ++lowered;
      }
    }
  EXPECT_GT(lowered, 20);
  EXPECT_GE(result.cells_lowered, lowered);
  EXPECT_GT(result.mean_lowering_m, 0.3);
}

TEST(HorizonLimit, LeavesGroundBetweenSeenGroundAndBehindObjects) {
  Scene between;  // the far side of the hollow is seen too: the hollow is interpolated
  between.Ring(2.0, 10.0, true, Rise);
  between.Ring(18.0, 22.0, true, [](double) { return 1.6; });
  Raster dem = Extrapolated();
  EXPECT_EQ(LimitToHorizon(between.points, between.ground, kViewpoint, {}, &dem).cells_lowered, 0);
  EXPECT_EQ(dem.values, Extrapolated().values);

  Scene tree;  // a canopy over the brow sets the horizon: the ground behind may rise
  tree.Ring(2.0, 10.0, true, Rise);
  tree.Ring(9.5, 9.5, false, [](double) { return 3.0; });
  EXPECT_EQ(LimitToHorizon(tree.points, tree.ground, kViewpoint, {}, &dem).cells_lowered, 0);

  Scene brow;
  brow.Ring(2.0, 10.0, true, Rise);
  HorizonLimitOptions off;
  off.enabled = false;
  EXPECT_EQ(LimitToHorizon(brow.points, brow.ground, kViewpoint, off, &dem).cells_lowered, 0);
  EXPECT_EQ(dem.values, Extrapolated().values);
}

TEST(HorizonLimit, RejectsBadInput) {
  Raster dem = Extrapolated();
  HorizonLimitOptions bad;
  bad.edge_m = 0.5;
  std::string why;
  EXPECT_FALSE(bad.Check(&why));
  EXPECT_NE(why.find("edge_m"), std::string::npos);
  EXPECT_THROW(LimitToHorizon({}, {}, kViewpoint, bad, &dem), std::invalid_argument);
  EXPECT_THROW(LimitToHorizon({{1, 0, 0}}, {}, kViewpoint, {}, &dem), std::invalid_argument);
}

}  // namespace
}  // namespace ts
