// The landform scenes of issue 22 are what their descriptions say, on every seed 1-5: the
// embankment's height and place, the terraces' treads and risers, the slope above the foot,
// the crest's flanks falling away, the badlands' relief; and where the ground hides itself
// from a tripod, a share of it is hidden (lines of sight through the terrain).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sim/scene.h"
#include "sim/scene_landforms.h"

namespace ts::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

double HeightAt(const Scene& s, double range_m, double azimuth_deg) {
  return s.TerrainHeight(range_m * std::sin(azimuth_deg * kDeg),
                         range_m * std::cos(azimuth_deg * kDeg));
}

// Share of the 1 m cells within `radius_m` of the station whose ground a camera 1.5 m above
// the mark cannot see (a terrain point on the line of sight above it).
double HiddenShare(const Scene& s, double radius_m) {
  const Eigen::Vector3d eye(0.0, 0.0, s.TerrainHeight(0, 0) + s.stage_height_m);
  int cells = 0, hidden = 0;
  for (double y = -radius_m + 0.5; y < radius_m; y += 1.0)
    for (double x = -radius_m + 0.5; x < radius_m; x += 1.0) {
      const double r = std::hypot(x, y);
      if (r > radius_m || r < 2.0) continue;
      ++cells;
      const Eigen::Vector3d target(x, y, s.TerrainHeight(x, y) + 0.05);
      for (double t = 0.02; t < 0.98; t += 0.25 / r) {
        const Eigen::Vector3d p = eye + t * (target - eye);
        if (s.TerrainHeight(p.x(), p.y()) > p.z()) {
          ++hidden;
          break;
        }
      }
    }
  return static_cast<double>(hidden) / cells;
}

// Highest minus lowest ground in the square of half side `half_m`.
double Relief(const Scene& s, double half_m) {
  double lo = 1e9, hi = -1e9;
  for (double y = -half_m; y <= half_m; y += 0.5)
    for (double x = -half_m; x <= half_m; x += 0.5) {
      const double h = s.TerrainHeight(x, y);
      lo = std::min(lo, h), hi = std::max(hi, h);
    }
  return hi - lo;
}

class Landforms : public ::testing::TestWithParam<int> {
 protected:
  Scene Make(const std::string& name) {
    Result<Scene> s = MakeBuiltinScene(name, GetParam());
    EXPECT_TRUE(s.ok()) << name;
    return s ? *std::move(s) : Scene{};
  }
};

// Some azimuth crosses the road square on: the ground 6-17 m out stands 1.5-2.5 m (up to the
// fields' own undulation) above the station's, and nothing of it lies within 5.5 m; the road
// is a line, crossing a quarter of the station's view or more within 17 m.
TEST_P(Landforms, EmbankmentCrossesTheNearFieldsAtItsHeight) {
  const Scene s = Make("embankment");
  const double h0 = s.TerrainHeight(0, 0);
  double highest = 0.0;
  int crossing = 0;
  for (double az = 0; az < 360; az += 1.0) {
    double top = -1e9, near = -1e9;
    for (double r = 6.0; r <= 17.0; r += 0.25) top = std::max(top, HeightAt(s, r, az) - h0);
    for (double r = 0.0; r <= 5.5; r += 0.25) near = std::max(near, HeightAt(s, r, az) - h0);
    highest = std::max(highest, top);
    crossing += top > 1.2;
    EXPECT_LT(near, 0.8) << "azimuth " << az;
  }
  EXPECT_GT(highest, 1.3);
  EXPECT_LT(highest, 3.0);
  EXPECT_GT(crossing, 90);
}

// Treads (under 10 % slope) cover most of the square, risers (steeper than 1:1) a few per
// cent; the station stands on a tread.
TEST_P(Landforms, TerracesAreTreadsAndRisers) {
  const Scene s = Make("terraces");
  int cells = 0, treads = 0, risers = 0;
  const auto slope_at = [&](double x, double y) {
    return std::hypot(s.TerrainHeight(x + 0.25, y) - s.TerrainHeight(x - 0.25, y),
                      s.TerrainHeight(x, y + 0.25) - s.TerrainHeight(x, y - 0.25)) /
           0.5;
  };
  for (double y = -30; y <= 30; y += 0.5)
    for (double x = -30; x <= 30; x += 0.5) {
      const double g = slope_at(x, y);
      ++cells, treads += g<0.1, risers += g> 1.0;
    }
  EXPECT_GT(treads, 0.6 * cells);
  EXPECT_GT(risers, 0.03 * cells);
  EXPECT_LT(slope_at(0, 0), 0.1);
  EXPECT_GT(Relief(s, 30), 8.0);
}

// Uphill the ground rises 25-40 m within 30 m of the station; behind it, it falls.
TEST_P(Landforms, FootOfASlopeRisingTwentyFiveToFortyMetres) {
  const Scene s = Make("foot");
  const double h0 = s.TerrainHeight(0, 0);
  double rise = 0.0, uphill = 0.0;
  for (double az = 0; az < 360; az += 1.0)
    if (HeightAt(s, 30.0, az) - h0 > rise) rise = HeightAt(s, 30.0, az) - h0, uphill = az;
  EXPECT_GT(rise, 22.0);
  EXPECT_LT(rise, 45.0);
  EXPECT_LT(HeightAt(s, 20.0, uphill + 180.0), h0 + 1.0);
  // Gullies: across the slope 20 m up, the ground dips a metre or more below its neighbours.
  double deepest = 0.0;
  for (double across = -25; across <= 25; across += 0.5) {
    const auto at = [&](double v) {
      return HeightAt(s, std::hypot(20.0, v), uphill + std::atan2(v, 20.0) / kDeg);
    };
    deepest = std::max(deepest, 0.5 * (at(across - 3) + at(across + 3)) - at(across));
  }
  EXPECT_GT(deepest, 1.0);
}

// On a crest: across it the ground 20 m out on both sides lies 4 m or more below the station,
// along it much less; the flanks beyond the brow are hidden.
TEST_P(Landforms, RidgeFallsAwayOnBothSides) {
  const Scene s = Make("ridge");
  const double h0 = s.TerrainHeight(0, 0);
  double best = -1e9, across = 0.0;
  for (double az = 0; az < 180; az += 1.0) {
    const double drop = h0 - std::max(HeightAt(s, 20.0, az), HeightAt(s, 20.0, az + 180.0));
    if (drop > best) best = drop, across = az;
  }
  EXPECT_GT(best, 4.0);
  const double along =
      h0 - std::max(HeightAt(s, 20.0, across + 90.0), HeightAt(s, 20.0, across + 270.0));
  EXPECT_LT(along, 3.0);
  EXPECT_GT(HiddenShare(s, 30.0), 0.4);
}

// 30-60 m of relief in the station's square, and gully floors hidden from it.
TEST_P(Landforms, BadlandsAreSteepAndHideTheirGullies) {
  const Scene s = Make("badlands");
  const double relief = Relief(s, 30.0);
  EXPECT_GT(relief, 30.0);
  EXPECT_LT(relief, 60.0);
  EXPECT_GT(HiddenShare(s, 30.0), 0.15);
}

INSTANTIATE_TEST_SUITE_P(Seeds, Landforms, ::testing::Values(1, 2, 3, 4, 5));

}  // namespace
}  // namespace ts::sim
