#include "processing/geometry/camera_model.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/common/paper_rig.h"

namespace ts {
namespace {

CameraIntrinsics StrongLens() {
  CameraIntrinsics c = testing::PaperCamera();
  c.principal_distance_px = 1860.0;
  c.principal_point_x_px = 701.3;
  c.principal_point_y_px = 512.8;
  c.k1 = -0.21;
  c.k2 = 0.15;
  c.k3 = -0.04;
  c.p1 = 8e-4;
  c.p2 = -5e-4;
  c.scale_x = 2e-4;
  c.shear = -1e-4;
  return c;
}

TEST(CameraModel, ProjectsPinholeExactly) {
  CameraIntrinsics c;
  c.width_px = 1000;
  c.height_px = 800;
  c.principal_distance_px = 1000.0;
  c.principal_point_x_px = 500.0;
  c.principal_point_y_px = 400.0;
  const CameraModel camera(c);
  Eigen::Vector2d pixel;
  ASSERT_TRUE(camera.Project({1.0, 2.0, 10.0}, &pixel));
  EXPECT_NEAR(pixel.x(), 600.0, 1e-12);
  EXPECT_NEAR(pixel.y(), 600.0, 1e-12);
}

// Seed 000 eq. 4 in pixel units: dx = xbar K1 r^2 with K1_seed = K1 / c^2.
TEST(CameraModel, RadialCorrectionMatchesSeedFormulaInPixels) {
  CameraIntrinsics c = StrongLens();
  c.k2 = c.k3 = c.p1 = c.p2 = c.scale_x = c.shear = 0.0;
  const CameraModel camera(c);
  const Eigen::Vector2d reduced(300.0, -200.0);
  const double r2_px = reduced.squaredNorm();
  const double k1_seed = c.k1 / (c.principal_distance_px * c.principal_distance_px);
  const Eigen::Vector2d pp(c.principal_point_x_px, c.principal_point_y_px);
  const Eigen::Vector2d ideal = camera.Undistort(pp + reduced);
  EXPECT_NEAR(ideal.x() - pp.x(), reduced.x() + reduced.x() * k1_seed * r2_px, 1e-9);
  EXPECT_NEAR(ideal.y() - pp.y(), reduced.y() + reduced.y() * k1_seed * r2_px, 1e-9);
}

// Seed 000 eqs. 4-5: affinity and shear terms dx = xbar Sx + ybar a, dy = xbar a.
TEST(CameraModel, AffinityAndShearMatchSeedFormula) {
  CameraIntrinsics c = StrongLens();
  c.k1 = c.k2 = c.k3 = c.p1 = c.p2 = 0.0;
  c.scale_x = 1e-3;
  c.shear = 2e-3;
  const CameraModel camera(c);
  const Eigen::Vector2d pp(c.principal_point_x_px, c.principal_point_y_px);
  const Eigen::Vector2d r(-250.0, 120.0);
  const Eigen::Vector2d ideal = camera.Undistort(pp + r) - pp;
  EXPECT_NEAR(ideal.x(), r.x() + r.x() * c.scale_x + r.y() * c.shear, 1e-9);
  EXPECT_NEAR(ideal.y(), r.y() + r.x() * c.shear, 1e-9);
}

// Decentring terms: dx = P1 (r^2 + 2 xbar^2) + 2 P2 xbar ybar, dy = 2 P1 xbar ybar + P2 (r^2 +
// 2 ybar^2), in normalised units times c.
TEST(CameraModel, DecentringMatchesSeedFormula) {
  CameraIntrinsics c = StrongLens();
  c.k1 = c.k2 = c.k3 = c.scale_x = c.shear = 0.0;
  const CameraModel camera(c);
  const double f = c.principal_distance_px;
  const Eigen::Vector2d pp(c.principal_point_x_px, c.principal_point_y_px);
  const Eigen::Vector2d r(400.0, 300.0);
  const double nx = r.x() / f, ny = r.y() / f, r2 = nx * nx + ny * ny;
  const Eigen::Vector2d ideal = camera.Undistort(pp + r) - pp;
  EXPECT_NEAR(ideal.x(), r.x() + f * (c.p1 * (r2 + 2 * nx * nx) + 2 * c.p2 * nx * ny), 1e-9);
  EXPECT_NEAR(ideal.y(), r.y() + f * (2 * c.p1 * nx * ny + c.p2 * (r2 + 2 * ny * ny)), 1e-9);
}

TEST(CameraModel, ProjectInvertsRayFromPixelOverTheWholeImage) {
  const CameraModel camera(StrongLens());
  for (int y = 0; y < 1040; y += 37) {
    for (int x = 0; x < 1392; x += 41) {
      const Eigen::Vector2d pixel(x + 0.25, y + 0.75);
      const Eigen::Vector3d ray = camera.RayFromPixel(pixel);
      EXPECT_NEAR(ray.norm(), 1.0, 1e-12);
      Eigen::Vector2d back;
      ASSERT_TRUE(camera.Project(17.0 * ray, &back)) << x << "," << y;
      EXPECT_NEAR((back - pixel).norm(), 0.0, 1e-8) << x << "," << y;
    }
  }
}

TEST(CameraModel, DistortInvertsUndistort) {
  const CameraModel camera(StrongLens());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, 1391.0), uy(0.0, 1039.0);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d pixel(ux(rng), uy(rng));
    Eigen::Vector2d back;
    ASSERT_TRUE(camera.Distort(camera.Undistort(pixel), &back));
    EXPECT_NEAR((back - pixel).norm(), 0.0, 1e-8);
  }
}

TEST(CameraModel, RejectsPointsBehindTheCamera) {
  const CameraModel camera(StrongLens());
  Eigen::Vector2d pixel;
  EXPECT_FALSE(camera.Project({0.1, 0.1, -5.0}, &pixel));
  EXPECT_FALSE(camera.Project({0.1, 0.1, 0.0}, &pixel));
}

TEST(CameraModel, PointJacobianMatchesNumeric) {
  const CameraModel camera(StrongLens());
  const Eigen::Vector3d p(2.1, -1.3, 9.0);
  Eigen::Vector2d pixel;
  CameraModel::Jacobian2x3 analytic;
  ASSERT_TRUE(camera.Project(p, &pixel, &analytic));
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d dp = Eigen::Vector3d::Zero();
    dp[k] = h;
    Eigen::Vector2d plus, minus;
    ASSERT_TRUE(camera.Project(p + dp, &plus));
    ASSERT_TRUE(camera.Project(p - dp, &minus));
    const Eigen::Vector2d numeric = (plus - minus) / (2 * h);
    EXPECT_NEAR((analytic.col(k) - numeric).norm(), 0.0, 1e-4 * (1.0 + numeric.norm())) << k;
  }
}

TEST(CameraModel, IntrinsicsJacobianMatchesNumeric) {
  const CameraIntrinsics base = StrongLens();
  const Eigen::Vector3d p(-3.0, 2.2, 8.0);
  Eigen::Vector2d pixel;
  CameraModel::JacobianIntrinsics analytic;
  ASSERT_TRUE(CameraModel(base).Project(p, &pixel, nullptr, &analytic));
  const auto params = base.ToParameters();
  for (int k = 0; k < CameraIntrinsics::kNumParameters; ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(params[k]));
    auto plus_params = params, minus_params = params;
    plus_params[k] += h;
    minus_params[k] -= h;
    Eigen::Vector2d plus, minus;
    ASSERT_TRUE(CameraModel(CameraIntrinsics::FromParameters(plus_params, 1392, 1040, 6.45))
                    .Project(p, &plus));
    ASSERT_TRUE(CameraModel(CameraIntrinsics::FromParameters(minus_params, 1392, 1040, 6.45))
                    .Project(p, &minus));
    const Eigen::Vector2d numeric = (plus - minus) / (2 * h);
    EXPECT_NEAR((analytic.col(k) - numeric).norm(), 0.0, 1e-5 * (1.0 + numeric.norm()))
        << CameraIntrinsics::kParameterNames[k];
  }
}

TEST(CameraModel, UndistortJacobianMatchesNumeric) {
  const CameraModel camera(StrongLens());
  const Eigen::Vector2d pixel(1200.0, 90.0);
  Eigen::Matrix2d analytic;
  camera.Undistort(pixel, &analytic);
  const double h = 1e-4;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    d[k] = h;
    const Eigen::Vector2d numeric =
        (camera.Undistort(pixel + d) - camera.Undistort(pixel - d)) / (2 * h);
    EXPECT_NEAR((analytic.col(k) - numeric).norm(), 0.0, 1e-7);
  }
}

TEST(CameraModel, CheckRejectsBadIntrinsics) {
  std::string why;
  CameraIntrinsics c = StrongLens();
  EXPECT_TRUE(c.Check(&why));
  c.principal_distance_px = 0.0;
  EXPECT_FALSE(c.Check(&why));
  EXPECT_NE(why.find("principal_distance_px"), std::string::npos);
  c = StrongLens();
  c.k2 = std::nan("");
  EXPECT_FALSE(c.Check(&why));
  EXPECT_NE(why.find("k2"), std::string::npos);
  c = StrongLens();
  c.width_px = 0;
  EXPECT_FALSE(c.Check(&why));
  // What no real camera is: a field of view under 1 or over 170 degrees, the principal point
  // off the sensor, a lens that moves its corner by more than half its distance from the axis.
  c = StrongLens();
  c.principal_distance_px = 0.5 * 1392 / std::tan(0.4 * M_PI / 360);
  EXPECT_FALSE(c.Check(&why));
  EXPECT_NE(why.find("field of view"), std::string::npos) << why;
  c.principal_distance_px = 0.5 * 1392 / std::tan(172 * M_PI / 360);
  EXPECT_FALSE(c.Check(&why));
  c = StrongLens();
  c.principal_point_y_px = -3.0;
  EXPECT_FALSE(c.Check(&why));
  EXPECT_NE(why.find("off the"), std::string::npos) << why;
  c = StrongLens();
  c.k1 = 1.2;  // the corner, 0.47 principal distances out: moved by 0.26 of its distance
  EXPECT_TRUE(c.Check(&why)) << why;
  c.k1 = 2.5;  // by 0.55
  EXPECT_FALSE(c.Check(&why));
  EXPECT_NE(why.find("no real lens"), std::string::npos) << why;
}

}  // namespace
}  // namespace ts
