// The room the ground has where kriging cannot know, against geometry with a known answer:
// ground seen on a crease (falling at 20 % to x = 10 m, rising at 20 % after it) except in a
// 6 m gap across it; the seen slopes turn by 0.4 there, so a cell d metres from the nearest
// ground point gets 0.4 d / 2 added (in quadrature) to its std. A seen cell across which the
// ground steps by 1 m gets the step's departure from the DEM's surface.
#include "processing/dem/ground_room.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ts {
namespace {

double Crease(double x) { return 0.2 * std::abs(x - 10.0); }

struct Site {
  KrigingPoints ground;
  Raster dem = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  Raster std = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  Site() {
    for (int r = 0; r < dem.rows; ++r)
      for (int c = 0; c < dem.cols; ++c) {
        dem.at(r, c) = static_cast<float>(Crease(dem.CellCentreX(c)));
        std.at(r, c) = 0.01f;
      }
    // Points every 0.25 m, none in the gap x, y in [7, 13).
    for (double y = 0.125; y < 20.0; y += 0.25)
      for (double x = 0.125; x < 20.0; x += 0.25) {
        if (x >= 7.0 && x < 13.0 && y >= 7.0 && y < 13.0) continue;
        ground.positions.emplace_back(x, y, Crease(x));
        ground.height_variances_m2.push_back(0.0);
      }
  }
};

TEST(GroundRoom, UnseenCellsGetTheSeenSlopesTurnOverTheirDistance) {
  Site site;
  const GroundRoomResult result = WidenStdByGroundRoom(site.ground, site.dem, {}, &site.std);
  EXPECT_EQ(result.unseen_cells, 36);
  // The gap's centre cell (x, y = 9.5, row 10 is y 9.5): 2.375 m from the nearest point.
  const double d = 9.5 - 6.875;
  EXPECT_NEAR(site.std.at(10, 9), std::hypot(0.01, 0.5 * 0.4 * d), 0.06);
  // A seen cell keeps kriging's std: the ground there is the DEM's surface.
  EXPECT_NEAR(site.std.at(2, 2), 0.01, 1e-4);
}

TEST(GroundRoom, ASeenCellAcrossAStepGetsTheStepsDeparture) {
  Site site;
  // The ground in cell (row 2, col 2) steps: its eastern half is 1 m higher than the DEM says.
  for (size_t i = 0; i < site.ground.positions.size(); ++i) {
    Eigen::Vector3d& p = site.ground.positions[i];
    if (p.x() >= 2.5 && p.x() < 3.0 && p.y() >= 17.0 && p.y() < 18.0) p.z() += 1.0;
  }
  WidenStdByGroundRoom(site.ground, site.dem, {}, &site.std);
  // Half of its points 1 m off: an RMS departure of sqrt(1/2).
  EXPECT_NEAR(site.std.at(2, 2), std::hypot(0.01, std::sqrt(0.5)), 0.01);
}

TEST(GroundRoom, EveryCellGetsAnEstimateCappedByTheLinesOfSight) {
  Site site;
  // A cell on the crease (x 10.5 m, y 16.5 m) without a DEM value, a line of sight 0.05 m up.
  site.dem.at(3, 10) = Raster::kNoData;
  site.std.at(3, 10) = Raster::kNoData;
  Raster ceiling = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  ceiling.at(3, 10) = 0.05f;  // below the crease's 0.1 there
  const GroundEstimate e = EstimateEveryCell(site.ground, site.dem, site.std, &ceiling, {});
  EXPECT_EQ(e.kind[static_cast<size_t>(3) * 20 + 10], CellGround::kEstimated);
  EXPECT_EQ(e.kind[static_cast<size_t>(10) * 20 + 10], CellGround::kUnseen);
  EXPECT_EQ(e.kind[static_cast<size_t>(2) * 20 + 2], CellGround::kSeen);
  EXPECT_FLOAT_EQ(e.height.at(3, 10), 0.05f);
  // A cell from its nearest neighbour with data, where the seen slopes turn by 0.4.
  EXPECT_NEAR(e.std.at(3, 10), std::hypot(0.01, 0.5 * 0.4 * 1.0), 0.02);
}

}  // namespace
}  // namespace ts
