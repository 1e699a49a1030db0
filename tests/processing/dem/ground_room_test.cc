// The room the ground has where kriging cannot know, against geometry with a known answer:
// ground seen on a crease (falling at 20 % to the middle of the square, rising at 20 % after
// it) except in a square gap across it; the seen slopes turn by 0.4 there, so a cell d metres
// from the nearest ground point gets 0.4 d / 2 added (in quadrature) to its std. A seen cell
// across which the ground steps by 1 m gets the step's departure from the DEM's surface.
#include "processing/dem/ground_room.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace ts {
namespace {

double Crease(double x, double middle = 10.0) { return 0.2 * std::abs(x - middle); }

// A square `size` metres wide, the gap x, y in [gap_from, size - gap_from).
struct Site {
  KrigingPoints ground;
  Raster dem, std;
  explicit Site(int size = 20, double gap_from = 7.0)
      : dem(Raster::Make(0.0, size, 1.0, size, size)),
        std(Raster::Make(0.0, size, 1.0, size, size)) {
    const double middle = 0.5 * size, gap_to = size - gap_from;
    for (int r = 0; r < dem.rows; ++r)
      for (int c = 0; c < dem.cols; ++c) {
        dem.at(r, c) = static_cast<float>(Crease(dem.CellCentreX(c), middle));
        std.at(r, c) = 0.01f;
      }
    // Points every 0.25 m, none in the gap.
    for (double y = 0.125; y < size; y += 0.25)
      for (double x = 0.125; x < size; x += 0.25) {
        if (x >= gap_from && x < gap_to && y >= gap_from && y < gap_to) continue;
        ground.positions.emplace_back(x, y, Crease(x, middle));
        ground.height_variances_m2.push_back(0.0);
      }
  }
};

// A 20 m square whose ground is profile(x): the DEM at the cell centres with kriging's std of
// 1 cm, and points every 0.25 m where seen(x, y).
struct ProfileSite {
  KrigingPoints ground;
  Raster dem, std;
};
template <class Profile, class Seen>
ProfileSite MakeProfileSite(const Profile& profile, const Seen& seen) {
  ProfileSite site{{}, Raster::Make(0.0, 20.0, 1.0, 20, 20), Raster::Make(0.0, 20.0, 1.0, 20, 20)};
  for (int r = 0; r < site.dem.rows; ++r)
    for (int c = 0; c < site.dem.cols; ++c) {
      site.dem.at(r, c) = static_cast<float>(profile(site.dem.CellCentreX(c)));
      site.std.at(r, c) = 0.01f;
    }
  for (double y = 0.125; y < 20.0; y += 0.25)
    for (double x = 0.125; x < 20.0; x += 0.25)
      if (seen(x, y)) site.ground.positions.emplace_back(x, y, profile(x));
  return site;
}

TEST(GroundRoom, UnseenCellsGetTheSeenSlopesTurnOverTheirDistance) {
  Site site;
  const GroundRoomResult result =
      WidenStdByGroundRoom(site.ground, site.dem, nullptr, {}, &site.std);
  EXPECT_EQ(result.unseen_cells, 36);
  // The gap's centre cell (x, y = 9.5, row 10 is y 9.5): 2.375 m from the nearest point.
  const double d = 9.5 - 6.875;
  EXPECT_NEAR(site.std.at(10, 9), std::hypot(0.01, 0.5 * 0.4 * d), 0.06);
  // A seen cell keeps kriging's std: the ground there is the DEM's surface.
  EXPECT_NEAR(site.std.at(2, 2), 0.01, 1e-4);
}

// Far into a gap, no seen ground lies within slope_window_m (5 m) of a cell: the turn is that of
// the seen ground within the distance the DEM is carried on over, not none.
TEST(GroundRoom, FarIntoAGapTheTurnIsTheSeenGroundsOverTheDistanceCarriedOn) {
  Site site(40, 8.0);  // the gap 24 m wide, the crease at x = 20 m
  WidenStdByGroundRoom(site.ground, site.dem, nullptr, {}, &site.std);
  // The cell at x = 19.5 m, y = 20.5 m (row 19, col 19): 11.625 m from the nearest point.
  const double d = 19.5 - 7.875;
  EXPECT_NEAR(site.std.at(19, 19), std::hypot(0.01, 0.5 * 0.4 * d), 0.1);
  // Every cell of the square for the terrain correction: a cell without a value in the gap's
  // middle is carried on a metre from its nearest cell with one (to the east: its other
  // neighbours have none either), whose std it widens by the turn over that metre.
  for (const auto& [r, c] : {std::pair{19, 19}, {18, 19}, {20, 19}, {19, 18}})
    site.dem.at(r, c) = site.std.at(r, c) = Raster::kNoData;
  const GroundEstimate e = EstimateEveryCell(site.ground, site.dem, site.std, nullptr, nullptr, {});
  EXPECT_NEAR(e.std.at(19, 19), std::hypot(site.std.at(19, 20), 0.5 * 0.4 * 1.0), 0.002);
}

TEST(GroundRoom, ASeenCellAcrossAStepGetsTheStepsDeparture) {
  Site site;
  // The ground in cell (row 2, col 2) steps: its eastern half is 1 m higher than the DEM says.
  for (size_t i = 0; i < site.ground.positions.size(); ++i) {
    Eigen::Vector3d& p = site.ground.positions[i];
    if (p.x() >= 2.5 && p.x() < 3.0 && p.y() >= 17.0 && p.y() < 18.0) p.z() += 1.0;
  }
  WidenStdByGroundRoom(site.ground, site.dem, nullptr, {}, &site.std);
  // Half of its points 1 m off: an RMS departure of sqrt(1/2).
  EXPECT_NEAR(site.std.at(2, 2), std::hypot(0.01, std::sqrt(0.5)), 0.01);
}

TEST(GroundRoom, EveryCellGetsAnEstimateCappedByTheLinesOfSight) {
  Site site;
  // A cell on the crease (x 10.5 m, y 16.5 m) without a DEM value, a line of sight 0.05 m up.
  site.dem.at(3, 10) = Raster::kNoData;
  site.std.at(3, 10) = Raster::kNoData;
  SightLineCeilings sight;
  sight.per_cell = sight.landing_per_cell = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  sight.per_cell.at(3, 10) = 0.05f;  // below the crease's 0.1 there
  sight.landing_per_cell.at(3, 10) = 0.0f;
  const GroundEstimate e = EstimateEveryCell(site.ground, site.dem, site.std, &sight, nullptr, {});
  EXPECT_EQ(e.kind[static_cast<size_t>(3) * 20 + 10], CellGround::kEstimated);
  EXPECT_EQ(e.kind[static_cast<size_t>(10) * 20 + 10], CellGround::kUnseen);
  EXPECT_EQ(e.kind[static_cast<size_t>(2) * 20 + 2], CellGround::kSeen);
  EXPECT_FLOAT_EQ(e.height.at(3, 10), 0.05f);
  // A cell from its nearest neighbour with data, where the seen slopes turn by 0.4.
  EXPECT_NEAR(e.std.at(3, 10), std::hypot(0.01, 0.5 * 0.4 * 1.0), 0.02);
}

// Where no line of sight passes over a cell without a value, the horizon over it caps it (the
// flank behind a ridge's brow falls away faster than the line over the brow); where one passes
// over, that line does, and the horizon, which the cell's ground may rise above if it was seen
// and not matched, does not.
TEST(GroundRoom, ACellNoLineCrossesIsCappedByTheHorizonOverIt) {
  Site site;
  for (const int c : {10, 11}) {
    site.dem.at(3, c) = Raster::kNoData;
    site.std.at(3, c) = Raster::kNoData;
  }
  SightLineCeilings sight;
  sight.per_cell = sight.landing_per_cell = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  sight.per_cell.at(3, 11) = 0.25f;  // the crease there stands at 0.3
  Raster horizon = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  horizon.at(3, 10) = 0.02f;  // the crease there stands at 0.1
  horizon.at(3, 11) = 0.02f;
  const GroundEstimate e = EstimateEveryCell(site.ground, site.dem, site.std, &sight, &horizon, {});
  EXPECT_FLOAT_EQ(e.height.at(3, 10), 0.02f);
  EXPECT_FLOAT_EQ(e.height.at(3, 11), 0.25f);
  const GroundEstimate without =
      EstimateEveryCell(site.ground, site.dem, site.std, &sight, nullptr, {});
  EXPECT_GT(without.height.at(3, 10), 0.05f);
}

// Behind a brow: the lowest line over the gap's centre cell grazed the brow and landed 1.2 m
// below the DEM there. The ground may lie anywhere down to that landing: the std is the RMS
// distance to it, 1.2 / sqrt(3), which exceeds the seen slopes' turn room (0.525 m). A seen
// cell under the same lines keeps kriging's std: its ground was seen.
TEST(GroundRoom, GroundHiddenBehindABrowMayLieDownToWhereTheLowestLineLanded) {
  Site site;
  SightLineCeilings sight;
  sight.per_cell = sight.landing_per_cell = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  for (int r : {10, 2}) {
    sight.per_cell.at(r, r == 10 ? 9 : 2) = site.dem.at(r, r == 10 ? 9 : 2) + 0.3f;
    sight.landing_per_cell.at(r, r == 10 ? 9 : 2) = site.dem.at(r, r == 10 ? 9 : 2) - 1.2f;
  }
  WidenStdByGroundRoom(site.ground, site.dem, &sight, {}, &site.std);
  EXPECT_NEAR(site.std.at(10, 9), std::hypot(0.01, 1.2 / std::sqrt(3.0)), 1e-4);
  EXPECT_NEAR(site.std.at(2, 2), 0.01, 1e-4);
  // A landing above the DEM leaves no room below: the turn's room stays.
  Site other;
  sight.landing_per_cell.at(10, 9) = other.dem.at(10, 9) + 0.5f;
  WidenStdByGroundRoom(other.ground, other.dem, &sight, {}, &other.std);
  EXPECT_NEAR(other.std.at(10, 9), std::hypot(0.01, 0.5 * 0.4 * (9.5 - 6.875)), 0.06);
}

// Ground kinked at x = 4 m (the seen slopes within 5 m turn by 0.4), seen up to x = 7.25 m.
// A seen cell with points all around its centre (x 6-7 m; the cubic surface through the cell
// centres from x = 4.5 m on is the ground's line) shows its own turns: kriging's std is left
// as it is. The centre of a cell seen only along its western edge (x 7-8 m) lies
// beyond the data, 0.5 m from them on the quarter-cell grid the distances are measured on:
// the turn's room 0.4 * 0.5 / 2 is added, or the room down to where a line over it landed.
TEST(GroundRoom, OnlyACellCentreBeyondItsPointsGetsTheRoomOfGroundNobodySaw) {
  ProfileSite site = MakeProfileSite([](double x) { return 0.2 * std::abs(x - 4.0); },
                                     [](double x, double) { return x < 7.25; });
  const KrigingPoints& ground = site.ground;
  const Raster& dem = site.dem;
  Raster& std = site.std;
  const Raster kriged_std = std;
  WidenStdByGroundRoom(ground, dem, nullptr, {}, &std);
  EXPECT_NEAR(std.at(10, 6), 0.01, 1e-4);
  EXPECT_NEAR(std.at(10, 7), std::hypot(0.01, 0.5 * 0.4 * 0.5), 0.005);

  // The same cells under lines of sight that grazed the lip at x = 7.25 m and landed on ground
  // 1.2 m below the DEM (a terrace's lower tread): the centre beyond the lip may lie anywhere
  // down to it, the one with points all around it may not.
  SightLineCeilings sight;
  sight.per_cell = sight.landing_per_cell = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  for (const int c : {6, 7}) {
    sight.per_cell.at(10, c) = dem.at(10, c) + 0.3f;
    sight.landing_per_cell.at(10, c) = dem.at(10, c) - 1.2f;
  }
  Raster under_lines = kriged_std;
  WidenStdByGroundRoom(ground, dem, &sight, {}, &under_lines);
  EXPECT_NEAR(under_lines.at(10, 6), 0.01, 1e-4);
  EXPECT_NEAR(under_lines.at(10, 7), std::hypot(0.01, 1.2 / std::sqrt(3.0)), 1e-4);
}

// The same lip, and one point of the lower tread seen 1.9 m south-east of the centre beyond
// it (a terrace's tread below the riser, seen past its end): the points that close the gap
// round a centre are those within a cell of its nearest point (1.5 m), not those in the
// square around it, whose corner this point stands in. The centre still lies beyond the lip.
TEST(GroundRoom, ACentreIsSurroundedOnlyByThePointsWithinACellOfItsNearest) {
  ProfileSite site = MakeProfileSite([](double x) { return 0.2 * std::abs(x - 4.0); },
                                     [](double x, double) { return x < 7.25; });
  site.ground.positions.emplace_back(8.875, 8.125, 0.2 * (8.875 - 4.0) - 1.2);
  WidenStdByGroundRoom(site.ground, site.dem, nullptr, {}, &site.std);
  EXPECT_NEAR(site.std.at(10, 7), std::hypot(0.01, 0.5 * 0.4 * 0.5), 0.005);
}

// Level ground seen all round a gap 7-13 m, and a face east of x = 15 m rising at 1 in 1 (a
// quarter of the seen cells): the station saw ground as steep as 1. The seen slopes within
// 5 m of the gap's centre turn by 0.25 at most, but no line of sight passed over the gap: its
// ground may fall away as steeply as the steep ground seen, anywhere down to 1 m per metre
// from the points, an RMS distance of 2.5 / sqrt(3) m at its centre (2.5 m from the points
// on the quarter-cell grid the distances are measured on). Where a line passed
// over it, or with the lines unknown, the turn's room stays; a carried-on cell without a value
// adds the steep slope over its step from its nearest cell with one.
TEST(GroundRoom, GroundNoLinePassedOverMayFallAsSteeplyAsTheSteepGroundSeen) {
  ProfileSite site = MakeProfileSite(
      [](double x) { return x < 15.0 ? 0.0 : x - 15.0; },
      [](double x, double y) { return x < 7.0 || x >= 13.0 || y < 7.0 || y >= 13.0; });
  const KrigingPoints& ground = site.ground;
  const Raster& dem = site.dem;
  const Raster kriged_std = site.std;
  SightLineCeilings none;
  none.per_cell = none.landing_per_cell = Raster::Make(0.0, 20.0, 1.0, 20, 20);
  const double d = 2.5;
  Raster std = kriged_std;
  WidenStdByGroundRoom(ground, dem, &none, {}, &std);
  EXPECT_NEAR(std.at(10, 9), std::hypot(0.01, 1.0 * d / std::sqrt(3.0)), 0.01);
  EXPECT_NEAR(std.at(2, 2), 0.01, 1e-4);  // seen

  SightLineCeilings over = none;
  over.per_cell.at(10, 9) = dem.at(10, 9) + 0.3f;
  over.landing_per_cell.at(10, 9) = dem.at(10, 9);
  for (const SightLineCeilings* sight : std::vector<const SightLineCeilings*>{&over, nullptr}) {
    Raster turned = kriged_std;
    WidenStdByGroundRoom(ground, dem, sight, {}, &turned);
    EXPECT_NEAR(turned.at(10, 9), std::hypot(0.01, 0.5 * 0.25 * d), 0.01);
  }
  GroundRoomOptions median;
  median.steep_slope_quantile = 0.5;  // the level ground's slope
  Raster level = kriged_std;
  WidenStdByGroundRoom(ground, dem, &none, median, &level);
  EXPECT_NEAR(level.at(10, 9), std::hypot(0.01, 0.5 * 0.25 * d), 0.01);

  // Without a value at the gap's centre cell: carried on a metre from its nearest neighbour with
  // one, whose std it widens by the steep slope over that metre.
  Raster gap = dem;
  gap.at(10, 9) = std.at(10, 9) = Raster::kNoData;
  const GroundEstimate e = EstimateEveryCell(ground, gap, std, &none, nullptr, {});
  double lowest = 1e9, highest = 0.0;
  for (const auto& [r, c] : {std::pair{9, 9}, {11, 9}, {10, 8}, {10, 10}}) {
    lowest = std::min(lowest, std::hypot(double(std.at(r, c)), 1.0 / std::sqrt(3.0)));
    highest = std::max(highest, std::hypot(double(std.at(r, c)), 1.0 / std::sqrt(3.0)));
  }
  EXPECT_GE(e.std.at(10, 9), lowest - 1e-4);
  EXPECT_LE(e.std.at(10, 9), highest + 1e-4);
}

}  // namespace
}  // namespace ts
