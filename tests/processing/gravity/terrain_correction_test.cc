#include "processing/gravity/terrain_correction.h"

#include <gtest/gtest.h>

#include <cmath>

#include "processing/gravity/prism.h"
#include "processing/gravity/terrain_correction_json.h"

namespace ts {
namespace {

const double kGrhoMgal = kGravitationalConstant * kStandardDensityKgM3 * kMgalPerMs2;

Raster Dem(double half_m, double cell_m, const std::function<double(double, double)>& height) {
  const int n = static_cast<int>(std::lround(2 * half_m / cell_m));
  Raster dem = Raster::Make(-half_m, half_m, cell_m, n, n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c)
      dem.at(r, c) = static_cast<float>(height(dem.CellCentreX(c), dem.CellCentreY(r)));
  return dem;
}

// An inclined plane through the station, z = x tan(a). A column at (r, theta) of height
// h = r tan(a) cos(theta) pulls with G rho dA (1/r - 1/sqrt(r^2 + h^2)); over the disc of
// radius R this is exactly linear in R:
//   TC = G rho R  integral_0^2pi (1 - 1 / sqrt(1 + tan^2(a) cos^2(theta))) d theta.
TEST(TerrainCorrection, InclinedPlaneWithinTwoPercentOfTheExactValue) {
  for (double slope_deg : {5.0, 15.0, 30.0}) {
    const double t = std::tan(slope_deg * M_PI / 180.0), radius = 30.0;
    double integral = 0.0;
    const int steps = 200000;
    for (int k = 0; k < steps; ++k) {
      const double c = std::cos((k + 0.5) * 2 * M_PI / steps);
      integral += (1.0 - 1.0 / std::sqrt(1.0 + t * t * c * c)) * 2 * M_PI / steps;
    }
    const double exact = kGrhoMgal * radius * integral;
    TerrainCorrectionOptions o;
    o.radius_m = radius;
    const TerrainCorrection tc = ComputeTerrainCorrection(
        Dem(35, 1.0, [t](double x, double) { return x * t; }), nullptr, {0, 0, 0}, o);
    EXPECT_NEAR(tc.total_mgal, exact, 0.02 * exact) << slope_deg << " deg";
    // Without refinement the staircase at the station is far off.
    o.refine_radius_m = 0.0;
    const double coarse =
        ComputeTerrainCorrection(Dem(35, 1.0, [t](double x, double) { return x * t; }), nullptr,
                                 {0, 0, 0}, o)
            .total_mgal;
    EXPECT_GT(std::abs(coarse - exact), std::abs(tc.total_mgal - exact)) << slope_deg;
  }
}

// A Hammer zone: a ring of flat terrain h above the station between r1 and r2 gives
// 2 pi G rho [r2 - r1 + sqrt(r1^2 + h^2) - sqrt(r2^2 + h^2)].
TEST(TerrainCorrection, HammerRingOfFlatTerrain) {
  const double r1 = 10.0, r2 = 30.0, h = 5.0;
  const double exact = 2 * M_PI * kGrhoMgal * (r2 - r1 + std::hypot(r1, h) - std::hypot(r2, h));
  const Raster dem = Dem(35, 0.25, [&](double x, double y) {
    const double d = std::hypot(x, y);
    return d >= r1 && d < r2 ? h : 0.0;
  });
  const TerrainCorrection tc = ComputeTerrainCorrection(dem, nullptr, {0, 0, 0}, {});
  EXPECT_NEAR(tc.total_mgal, exact, 0.01 * exact);
  // All of it in the rings 10-20 and 20-30 m, a quarter in each quadrant.
  EXPECT_NEAR(tc.rings[2].mgal + tc.rings[3].mgal, tc.total_mgal, 1e-9);
  for (double q : tc.quadrant_mgal) EXPECT_NEAR(q, 0.25 * tc.total_mgal, 0.01 * tc.total_mgal);
}

// A cylindrical pit of radius a and depth h centred under the station: the missing mass of
// a cylinder at the centre of its top face, 2 pi G rho [h + a - sqrt(a^2 + h^2)].
TEST(TerrainCorrection, CylinderOnItsAxis) {
  const double a = 10.0, h = 3.0;
  const double exact = 2 * M_PI * kGrhoMgal * (h + a - std::hypot(a, h));
  const Raster dem =
      Dem(15, 0.25, [&](double x, double y) { return std::hypot(x, y) < a ? -h : 0.0; });
  TerrainCorrectionOptions o;
  o.refine_radius_m = 0.0;  // the point floats over the pit: no mark on the surface to tie to
  EXPECT_NEAR(ComputeTerrainCorrection(dem, nullptr, {0, 0, 0}, o).total_mgal, exact, 0.01 * exact);
}

// Terrain at the station's height everywhere: nothing to correct; a pit and a hill of the
// same size both raise the correction; a bump below the raised sensor lowers it.
TEST(TerrainCorrection, SignsOfHillsPitsAndBumpsBelowTheSensor) {
  TerrainCorrectionOptions o;
  EXPECT_NEAR(ComputeTerrainCorrection(Dem(20, 1, [](double, double) { return 3.0; }), nullptr,
                                       {0, 0, 3.0}, o)
                  .total_mgal,
              0.0, 1e-12);
  auto bump = [](double height) {
    return [height](double x, double y) { return std::hypot(x - 8, y - 3) < 2 ? height : 0.0; };
  };
  const double hill =
      ComputeTerrainCorrection(Dem(20, 1, bump(2.0)), nullptr, {0, 0, 0}, o).total_mgal;
  const double pit =
      ComputeTerrainCorrection(Dem(20, 1, bump(-2.0)), nullptr, {0, 0, 0}, o).total_mgal;
  EXPECT_GT(hill, 0.0);
  EXPECT_NEAR(pit, hill, 1e-9);  // mirror images at sensor height 0
  o.sensor_height_m = 1.0;
  const double small_bump_below_sensor =
      ComputeTerrainCorrection(Dem(20, 1, bump(0.5)), nullptr, {0, 0, 0}, o).total_mgal;
  EXPECT_LT(small_bump_below_sensor, 0.0);
}

// The mark is a known ground point: a DEM 0.3 m off at the station is tied to it there.
TEST(TerrainCorrection, TiesTheSurfaceToTheStationMark) {
  const double t = std::tan(10 * M_PI / 180.0);
  TerrainCorrectionOptions o;
  o.radius_m = 20;
  const double right = ComputeTerrainCorrection(Dem(25, 1, [t](double x, double) { return x * t; }),
                                                nullptr, {0, 0, 0}, o)
                           .total_mgal;
  const TerrainCorrection shifted =
      ComputeTerrainCorrection(Dem(25, 1,
                                   [t](double x, double y) {
                                     return x * t + 0.3 * std::max(0.0, 1 - std::hypot(x, y) / 6);
                                   }),
                               nullptr, {0, 0, 0}, o);
  EXPECT_NEAR(shifted.station_misfit_m, 0.3 * (1 - M_SQRT1_2 / 6), 1e-6);  // bilinear at the mark
  EXPECT_NEAR(shifted.total_mgal, right, 0.01 * right);
}

// The sigma from the DEM's std, cells independent, and the correlated bound above it. Where
// the std is small against the ground's height differences the correction is linear in each
// cell's height over it: halving the std halves both.
TEST(TerrainCorrection, SigmaFromTheDemStd) {
  const Raster dem = Dem(20, 1, [](double x, double y) { return 0.1 * x + 0.05 * y * y / 10; });
  Raster std_dev = dem;
  std::fill(std_dev.values.begin(), std_dev.values.end(), 0.02f);
  const TerrainCorrection tc = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, {});
  EXPECT_GT(tc.sigma_mgal, 0.0);
  EXPECT_GT(tc.sigma_correlated_mgal, tc.sigma_mgal);
  std::fill(std_dev.values.begin(), std_dev.values.end(), 0.01f);
  const TerrainCorrection half = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, {});
  EXPECT_NEAR(half.sigma_mgal, 0.5 * tc.sigma_mgal, 0.01 * tc.sigma_mgal);
  EXPECT_NEAR(half.sigma_correlated_mgal, 0.5 * tc.sigma_correlated_mgal,
              0.01 * tc.sigma_correlated_mgal);
  EXPECT_EQ(ComputeTerrainCorrection(dem, nullptr, {0, 0, 0}, {}).sigma_mgal, 0.0);
}

// A cell's sigma is the spread of its correction over its height's distribution, against that
// spread integrated finely (the correction itself at 481 heights over +-6 std, weighted by the
// normal density): ground at the mark's height with a std of 1.5 m (the slope there is zero:
// a linearised sigma would be none), 3 m above it, and 9 m below it. Three points are exact
// for a quadratic; the prism at the sensor's own height is nearly one.
TEST(TerrainCorrection, ACellsSigmaIsTheSpreadOfItsCorrectionNotItsSlope) {
  Raster dem = Raster::Make(-20.0, 20.0, 1.0, 40, 40);
  std::fill(dem.values.begin(), dem.values.end(), Raster::kNoData);
  const int r = 10, c = 28;  // one cell 8.5 m east, 9.5 m north of the mark
  const double s = 1.5;
  Raster std_dev = dem;
  std_dev.at(r, c) = static_cast<float>(s);
  for (const double height : {0.0, 3.0, -9.0}) {
    dem.at(r, c) = static_cast<float>(height);
    const TerrainCorrection tc = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, {});
    double weight = 0.0, sum = 0.0, sum2 = 0.0;
    for (int i = -240; i <= 240; ++i) {
      const double u = i / 40.0, w = std::exp(-0.5 * u * u);
      Raster drawn = dem;
      drawn.at(r, c) = static_cast<float>(height + s * u);
      const double v = ComputeTerrainCorrection(drawn, nullptr, {0, 0, 0}, {}).total_mgal;
      weight += w, sum += w * v, sum2 += w * v * v;
    }
    const double sigma = std::sqrt(sum2 / weight - (sum / weight) * (sum / weight));
    EXPECT_GT(tc.sigma_mgal, 0.0) << height;
    EXPECT_NEAR(tc.sigma_mgal, sigma, 0.05 * sigma) << height;  // 2.9 % at the mark's height
  }
}

TEST(TerrainCorrection, WarnsWhereARingIsThinlyCovered) {
  Raster dem = Dem(35, 1, [](double x, double) { return 0.2 * x; });
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c)
      if (std::hypot(dem.CellCentreX(c), dem.CellCentreY(r)) > 20 && dem.CellCentreX(c) < 0)
        dem.at(r, c) = Raster::kNoData;
  const TerrainCorrection tc = ComputeTerrainCorrection(dem, nullptr, {0, 0, 0}, {});
  EXPECT_GT(tc.rings[1].coverage, 0.99);
  EXPECT_LT(tc.rings[3].coverage, 0.6);
  ASSERT_FALSE(tc.warnings.empty());
  EXPECT_NE(tc.warnings.front().find("ring 20-30 m"), std::string::npos) << tc.warnings.front();
}

// The far field changes a rough 60 m DEM's correction by under 0.1 % (and every ring's).
TEST(TerrainCorrection, FarFieldAgreesWithExactPrisms) {
  const Raster dem = Dem(30, 1.0, [](double x, double y) {
    return 2.0 * std::sin(x / 7.0) * std::cos(y / 5.0) + 0.05 * x;
  });
  TerrainCorrectionOptions exact, far;
  exact.far_field_ratio = 0.0;
  const Eigen::Vector3d mark(0.0, 0.0, dem.Interpolate(0.0, 0.0));
  const TerrainCorrection a = ComputeTerrainCorrection(dem, nullptr, mark, exact);
  const TerrainCorrection b = ComputeTerrainCorrection(dem, nullptr, mark, far);
  EXPECT_GT(a.total_mgal, 0.01);
  EXPECT_NEAR(b.total_mgal, a.total_mgal, 1e-3 * a.total_mgal);
  for (size_t k = 0; k < a.rings.size(); ++k)
    EXPECT_NEAR(b.rings[k].mgal, a.rings[k].mgal, 1e-3 * std::abs(a.rings[k].mgal) + 1e-9) << k;
}

TEST(TerrainCorrection, RejectsBadOptions) {
  TerrainCorrectionOptions o;
  o.density_kg_m3 = 0;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_THROW(ComputeTerrainCorrection(Dem(5, 1, [](double, double) { return 0.0; }), nullptr,
                                        {0, 0, 0}, o),
               std::invalid_argument);
}

}  // namespace
}  // namespace ts

namespace ts {
namespace {

// Ground nobody saw is one unknown: its cells' sigmas add linearly (and make up the rings'
// unseen sigma); seen cells add in quadrature. On a 2 m bump with std 0.1 m in every cell:
// all seen gives the independent sum, all unseen the fully correlated one.
TEST(TerrainCorrection, UnseenGroundIsOneUnknownSeenCellsAreIndependent) {
  Raster dem = Raster::Make(-20.0, 20.0, 1.0, 40, 40);
  Raster std_dev = dem;
  for (float& v : dem.values) v = 2.0f;
  for (float& v : std_dev.values) v = 0.1f;
  const Eigen::Vector3d mark(0.0, 0.0, 0.0);
  std::vector<CellGround> seen(dem.values.size(), CellGround::kSeen);
  std::vector<CellGround> unseen(dem.values.size(), CellGround::kUnseen);
  const TerrainCorrection a = ComputeTerrainCorrection(dem, &std_dev, mark, {}, &seen);
  const TerrainCorrection b = ComputeTerrainCorrection(dem, &std_dev, mark, {}, &unseen);
  EXPECT_DOUBLE_EQ(a.total_mgal, b.total_mgal);
  EXPECT_EQ(a.sigma_unseen_mgal, 0.0);
  EXPECT_LT(a.sigma_mgal, 0.5 * a.sigma_correlated_mgal);
  EXPECT_NEAR(b.sigma_mgal, b.sigma_correlated_mgal, 1e-12);
  EXPECT_NEAR(b.sigma_unseen_mgal, b.sigma_correlated_mgal, 1e-12);
  double rings = 0.0;
  for (const RingContribution& r : b.rings) rings += r.sigma_unseen_mgal;
  EXPECT_NEAR(rings, b.sigma_unseen_mgal, 1e-12);
  EXPECT_EQ(b.rings[1].sectors[0].seen, 0.0);  // data, but nobody saw it
  EXPECT_EQ(b.rings[1].sectors[0].coverage, 1.0);
  // Estimated cells count as without data in the rings' coverage.
  std::vector<CellGround> estimated(dem.values.size(), CellGround::kEstimated);
  const TerrainCorrection c = ComputeTerrainCorrection(dem, &std_dev, mark, {}, &estimated);
  EXPECT_EQ(c.rings[1].coverage, 0.0);
  EXPECT_DOUBLE_EQ(c.total_mgal, a.total_mgal);
}

// The sectors say which way a thin ring is thin: the 10-20 m ring without data due east
// (bearing 90 deg, x > 0 in frame L) and with a std only there. Each sector's sigma adds up to
// its ring's in quadrature (seen cells are independent).
TEST(TerrainCorrection, SectorsNameTheDirectionOfAThinRing) {
  Raster dem = Dem(35, 1, [](double x, double y) { return 0.1 * x + 0.02 * y; });
  Raster std_dev = dem;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double x = dem.CellCentreX(c), y = dem.CellCentreY(r), d = std::hypot(x, y);
      const double bearing = std::atan2(x, y) * 180.0 / M_PI;
      const bool east = std::abs(bearing - 90.0) < 15.0;
      std_dev.at(r, c) = d >= 10 && d < 20 && std::abs(bearing - 60.0) < 15.0 ? 0.5f : 0.05f;
      if (d >= 10 && d < 20 && east) dem.at(r, c) = Raster::kNoData;
    }
  const TerrainCorrection tc = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, {});
  const RingContribution& ring = tc.rings[2];
  ASSERT_EQ(ring.sectors.size(), static_cast<size_t>(kSectors));
  double variance = 0.0;
  for (int k = 0; k < kSectors; ++k) {
    const SectorContribution& s = ring.sectors[k];
    EXPECT_DOUBLE_EQ(s.bearing_deg, 30.0 * k);
    EXPECT_EQ(s.coverage, k == 3 ? 0.0 : 1.0) << "sector " << k;
    EXPECT_EQ(s.seen, s.coverage) << "sector " << k;  // no ground kinds given: data is seen
    variance += s.sigma_mgal * s.sigma_mgal;
    if (k != 2) {
      EXPECT_LT(s.sigma_mgal, 0.5 * ring.sectors[2].sigma_mgal) << "sector " << k;
    }
  }
  EXPECT_NEAR(std::sqrt(variance), ring.sigma_mgal, 1e-9);
  EXPECT_NEAR(ring.coverage, 11.0 / 12.0, 0.02);
  const nlohmann::json j = TerrainCorrectionToJson(tc, {}, {0, 0, 0});
  EXPECT_EQ(j["rings"][2]["sectors"][3]["coverage"], 0.0);
  EXPECT_EQ(j["rings"][2]["sectors"][3]["bearing_deg"], 90.0);
}

// Estimated from too little seen ground, a correction has no value: unusable, with the
// reason, whatever its sigma says. A DEM with data only in a strip along one edge: a tenth of
// the ground within 30 m, a third within 10 m.
TEST(TerrainCorrection, TooLittleSeenGroundIsUnusableNotATightSigma) {
  Raster dem = Raster::Make(-30, 30, 1.0, 60, 60);
  Raster std_dev = dem;
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 60; ++c)
      if (dem.CellCentreX(c) > 6.0 ||
          (std::abs(dem.CellCentreX(c)) < 2 && std::abs(dem.CellCentreY(r)) < 2))
        dem.at(r, c) = 0.1f * static_cast<float>(dem.CellCentreX(c)), std_dev.at(r, c) = 0.01f;
  TerrainCorrectionOptions o;
  TerrainCorrection tc = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, o);
  EXPECT_FALSE(tc.Usable());
  EXPECT_NE(tc.unusable_because.find("of the ground within 10 m has DEM data (50 % needed)"),
            std::string::npos)
      << tc.unusable_because;
  const nlohmann::json j = TerrainCorrectionToJson(tc, o, {0, 0, 0});
  EXPECT_TRUE(j["terrain_correction_mgal"].is_null());
  EXPECT_TRUE(j["sigma_mgal"].is_null());
  EXPECT_EQ(j["verdict"], "unusable");
  // The same ground seen all round is usable.
  for (float& v : dem.values)
    if (Raster::IsNoData(v)) v = 0.0f;
  for (float& v : std_dev.values)
    if (Raster::IsNoData(v)) v = 0.01f;
  tc = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, o);
  EXPECT_TRUE(tc.Usable()) << tc.unusable_because;
  EXPECT_EQ(TerrainCorrectionToJson(tc, o, {0, 0, 0})["verdict"], "usable");
  // Data everywhere, but kriged from a few points: one cell in 25 seen (4 %) is unusable, one
  // in 4 (25 %) is not.
  for (int every : {5, 2}) {
    std::vector<CellGround> kind(dem.values.size(), CellGround::kUnseen);
    for (int r = 0; r < 60; r += every)
      for (int c = 0; c < 60; c += every) kind[static_cast<size_t>(r) * 60 + c] = CellGround::kSeen;
    tc = ComputeTerrainCorrection(dem, &std_dev, {0, 0, 0}, o, &kind);
    EXPECT_EQ(tc.Usable(), every == 2) << every << ": " << tc.unusable_because;
    if (every == 5) {
      EXPECT_NE(tc.unusable_because.find("of the ground within 30 m was seen"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace ts
