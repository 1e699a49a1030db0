#include "processing/geometry/theoretical_accuracy.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "processing/geometry/intersection.h"
#include "processing/geometry/stereo_rig.h"
#include "tests/common/paper_rig.h"

namespace ts {
namespace {

// The paper's rig (seed 003 table 1): B = 0.5 m, f = 12 mm, 6.45 um pixels.
constexpr double kBaselineM = 0.5;
constexpr double kFocalPx = 12.0e-3 / 6.45e-6;

TEST(TheoreticalAccuracy, PaperRigMatchesFigure2) {
  const auto rows = TheoreticalAccuracy(kBaselineM, kFocalPx, {});
  ASSERT_EQ(rows.size(), 12u);  // 5, 10, ..., 60 m
  EXPECT_DOUBLE_EQ(rows.front().range_m, 5.0);
  EXPECT_DOUBLE_EQ(rows.back().range_m, 60.0);
  // sigma_Y(30 m) = 900 / (0.5 * 1860.47) / 3 = 0.3225 m; the paper reads ~0.32 m.
  EXPECT_NEAR(rows[5].range_m, 30.0, 1e-12);
  EXPECT_NEAR(rows[5].sigma_y_m, 0.3225, 5e-4);
  for (const AccuracyRow& r : rows) {
    if (r.range_m <= 50.0) {
      EXPECT_LT(r.sigma_y_m, 1.0) << r.range_m;
    }
    EXPECT_LE(r.sigma_x_m, r.sigma_y_m);
    EXPECT_LE(r.sigma_z_m, r.sigma_y_m);
  }
}

TEST(TheoreticalAccuracy, RangeErrorGrowsWithTheSquareOfRange) {
  TheoreticalAccuracyOptions o;
  o.range_min_m = 10;
  o.range_max_m = 40;
  o.range_step_m = 10;
  const auto rows = TheoreticalAccuracy(kBaselineM, kFocalPx, o);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_NEAR(rows[3].sigma_y_m / rows[1].sigma_y_m, 4.0, 1e-12);  // 40 m vs 20 m
}

TEST(TheoreticalAccuracy, AtThePrincipalPointLateralErrorIsYOverF) {
  TheoreticalAccuracyOptions o;
  o.sigma_image_px = 0.5;
  const auto rows = TheoreticalAccuracy(kBaselineM, kFocalPx, o);
  for (const AccuracyRow& r : rows) {
    EXPECT_NEAR(r.sigma_x_m, r.range_m / kFocalPx * 0.5, 1e-12);
    EXPECT_NEAR(r.sigma_z_m, r.range_m / kFocalPx * 0.5, 1e-12);
  }
}

// Eq. 1's sigma_Y is the intersection's sigma_Y when sigma_p is the parallax error of two
// image coordinates of sigma_p / sqrt(2) each.
TEST(TheoreticalAccuracy, AgreesWithIntersectionCovariance) {
  const CameraModel camera(testing::PaperCamera());
  const auto rows = TheoreticalAccuracy(kBaselineM, kFocalPx, {});
  for (const AccuracyRow& row : rows) {
    const Eigen::Vector3d point(0.0, row.range_m, 0.0);
    std::vector<RayObservation> rays;
    for (double x : {-kBaselineM / 2, kBaselineM / 2}) {
      RayObservation ray;
      ray.camera = &camera;
      ray.world_from_camera.linear() = StereoRig::NominalSFromCamera();
      ray.world_from_camera.translation() = Eigen::Vector3d(x, 0, 0);
      ASSERT_TRUE(camera.Project(ray.world_from_camera.inverse() * point, &ray.pixel));
      ray.sigma_px = (1.0 / 3.0) / std::sqrt(2.0);
      rays.push_back(ray);
    }
    const IntersectionResult r = IntersectRays(rays);
    ASSERT_TRUE(r.usable);
    EXPECT_NEAR(std::sqrt(r.covariance_m2(1, 1)), row.sigma_y_m, 1e-6 * row.sigma_y_m);
  }
}

TEST(TheoreticalAccuracy, RejectsBadOptions) {
  TheoreticalAccuracyOptions o;
  o.sigma_parallax_px = -1;
  EXPECT_THROW(TheoreticalAccuracy(kBaselineM, kFocalPx, o), std::invalid_argument);
  o = {};
  o.range_step_m = 0;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_THROW(TheoreticalAccuracy(0.0, kFocalPx, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ts
