#include "processing/geometry/intersection.h"

#include <gtest/gtest.h>

#include <random>

#include "processing/geometry/rotation.h"
#include "processing/geometry/stereo_rig.h"
#include "tests/common/paper_rig.h"

namespace ts {
namespace {

CameraIntrinsics Lens(bool distorted) {
  CameraIntrinsics c = testing::PaperCamera();
  c.principal_distance_px = 1860.0;
  if (distorted) {
    c.k1 = -0.15;
    c.k2 = 0.08;
    c.p1 = 3e-4;
  }
  return c;
}

// Camera looking along +Y (the rig's nominal orientation) centred at (x, 0, 0).
Eigen::Isometry3d NormalCase(double x) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = StereoRig::NominalSFromCamera();
  t.translation() = Eigen::Vector3d(x, 0, 0);
  return t;
}

RayObservation Observe(const CameraModel& camera, const Eigen::Isometry3d& pose,
                       const Eigen::Vector3d& point, double sigma_px) {
  RayObservation ray;
  ray.camera = &camera;
  ray.world_from_camera = pose;
  EXPECT_TRUE(camera.Project(pose.inverse() * point, &ray.pixel));
  ray.sigma_px = sigma_px;
  return ray;
}

TEST(Intersection, RecoversPointFromTwoPerfectRays) {
  const CameraModel camera(Lens(true));
  const Eigen::Vector3d point(3.2, 27.0, -1.4);
  const auto rays = std::vector{Observe(camera, NormalCase(-0.25), point, 0.3),
                                Observe(camera, NormalCase(0.25), point, 0.3)};
  const IntersectionResult r = IntersectRays(rays);
  ASSERT_TRUE(r.usable) << r.why;
  EXPECT_NEAR((r.point_world - point).norm(), 0.0, 1e-8);
  EXPECT_LT(r.rms_residual_px, 1e-8);
}

TEST(Intersection, RecoversPointFromThreeRotatedCameras) {
  const CameraModel camera(Lens(true));
  const Eigen::Vector3d point(-4.0, 18.0, -2.5);
  std::vector<RayObservation> rays;
  for (double x : {-1.0, 0.2, 1.5}) {
    Eigen::Isometry3d pose = NormalCase(x);
    pose.linear() = RotationZ(0.05 * x) * pose.linear() * RotationFromOpk({0.01, -0.02 * x, 0.03});
    pose.translation().z() = 0.3 * x;
    rays.push_back(Observe(camera, pose, point, 0.25));
  }
  const IntersectionResult r = IntersectRays(rays);
  ASSERT_TRUE(r.usable) << r.why;
  EXPECT_NEAR((r.point_world - point).norm(), 0.0, 1e-8);
}

// Normal case, point on the midline at depth Y: depth comes from the x-parallax p = x_l - x_r
// with sigma_p = sqrt(2) sigma, so sigma_Y = Y^2 / (B f) sqrt(2) sigma; X from the mean of
// x_l and x_r: sigma_X = Y sigma / (sqrt(2) f); Z likewise from y_l and y_r.
TEST(Intersection, CovarianceMatchesNormalCaseFormulas) {
  const CameraModel camera(Lens(false));
  const double b = 0.5, f = 1860.0, sigma = 0.2;
  for (double y : {5.0, 20.0, 45.0}) {
    const Eigen::Vector3d point(0.0, y, 0.0);
    const auto rays = std::vector{Observe(camera, NormalCase(-b / 2), point, sigma),
                                  Observe(camera, NormalCase(b / 2), point, sigma)};
    const IntersectionResult r = IntersectRays(rays);
    ASSERT_TRUE(r.usable);
    const double sigma_y = y * y / (b * f) * std::sqrt(2.0) * sigma;
    const double sigma_xz = y * sigma / (std::sqrt(2.0) * f);
    EXPECT_NEAR(std::sqrt(r.covariance_m2(1, 1)), sigma_y, 1e-6 * sigma_y);
    EXPECT_NEAR(std::sqrt(r.covariance_m2(0, 0)), sigma_xz, 1e-6 * sigma_xz);
    EXPECT_NEAR(std::sqrt(r.covariance_m2(2, 2)), sigma_xz, 1e-6 * sigma_xz);
  }
}

// The predicted covariance must describe the scatter of intersections of noisy rays.
TEST(Intersection, CovarianceAgreesWithMonteCarlo) {
  const CameraModel camera(Lens(true));
  const Eigen::Vector3d point(6.0, 22.0, -1.6);
  const double sigma = 0.3;
  auto rays = std::vector{Observe(camera, NormalCase(-0.25), point, sigma),
                          Observe(camera, NormalCase(0.25), point, sigma)};
  const IntersectionResult nominal = IntersectRays(rays);
  ASSERT_TRUE(nominal.usable);
  const auto perfect = rays;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, sigma);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    for (size_t k = 0; k < rays.size(); ++k)
      rays[k].pixel = perfect[k].pixel + Eigen::Vector2d(noise(rng), noise(rng));
    const IntersectionResult r = IntersectRays(rays);
    ASSERT_TRUE(r.usable);
    const Eigen::Vector3d e = r.point_world - point;
    scatter += e * e.transpose();
  }
  scatter /= n;
  for (int k = 0; k < 3; ++k) {
    const double ratio = std::sqrt(scatter(k, k) / nominal.covariance_m2(k, k));
    EXPECT_NEAR(ratio, 1.0, 0.05) << "axis " << k;
  }
}

TEST(Intersection, RefusesDegenerateInput) {
  const CameraModel camera(Lens(false));
  const Eigen::Vector3d point(0.0, 20.0, 0.0);
  RayObservation one = Observe(camera, NormalCase(0.0), point, 0.3);
  IntersectionResult r = IntersectRays({one});
  EXPECT_FALSE(r.usable);
  EXPECT_NE(r.why.find("two rays"), std::string::npos);
  // Two identical rays from the same centre are parallel.
  r = IntersectRays({one, one});
  EXPECT_FALSE(r.usable);
  EXPECT_NE(r.why.find("parallel"), std::string::npos);
  RayObservation bad = one;
  bad.sigma_px = 0.0;
  EXPECT_FALSE(IntersectRays({one, bad}).usable);
  bad = one;
  bad.camera = nullptr;
  EXPECT_FALSE(IntersectRays({one, bad}).usable);
}

TEST(Intersection, RejectsRaysThatMeetBehindTheCameras) {
  const CameraModel camera(Lens(false));
  // Rays diverging: left looks left, right looks right; their lines meet behind the bar.
  RayObservation left = Observe(camera, NormalCase(-0.25), {-5.0, 10.0, 0.0}, 0.3);
  RayObservation right = Observe(camera, NormalCase(0.25), {5.0, 10.0, 0.0}, 0.3);
  const IntersectionResult r = IntersectRays({left, right});
  EXPECT_FALSE(r.usable);
  EXPECT_NE(r.why.find("behind"), std::string::npos);
}

}  // namespace
}  // namespace ts
