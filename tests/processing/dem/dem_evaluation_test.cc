#include "processing/dem/dem_evaluation.h"

#include <gtest/gtest.h>

namespace ts {
namespace {

// A DEM of the 60 m square 0.1 m off the truth within 30 m of the station and 1 m off beyond
// (the square's corners): the near region's RMSE is 0.1 m exactly, the square's the mean of the
// squares by cell count.
TEST(DemEvaluation, TheNearRegionsRmseLeavesOutTheSquaresCorners) {
  const Eigen::Vector2d station(0.5, -0.5);  // off the grid's centre: the circle is the mark's
  Raster truth = Raster::Make(-30, 30, 1.0, 60, 60, 5.0f);
  Raster dem = truth;
  int near = 0, far = 0;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const bool inside =
          (Eigen::Vector2d(dem.CellCentreX(c), dem.CellCentreY(r)) - station).norm() <= 30.0;
      dem.at(r, c) += inside ? 0.1f : 1.0f;
      (inside ? near : far) += 1;
    }
  dem.at(0, 0) = Raster::kNoData;  // a corner without data is in neither
  --far;
  const DemEvaluation e = EvaluateDem(dem, truth, station);
  EXPECT_NEAR(e.rmse_30m_m, 0.1, 1e-6);
  EXPECT_NEAR(e.rmse_m, std::sqrt((near * 0.01 + far * 1.0) / (near + far)), 1e-6);
  EXPECT_EQ(e.cells_compared, near + far);
  EXPECT_NEAR(e.ToJson()["dem_rmse_30m_m"].get<double>(), 0.1, 1e-6);
  EXPECT_TRUE(std::isnan(EvaluateDem(dem, truth, {100.0, 100.0}).rmse_30m_m))
      << "no cell within 30 m";
}

}  // namespace
}  // namespace ts
