// Intersection of rectified matches against known points, and against the general N-ray
// intersection of the same rays in the original (distorted) images.
#include "processing/matching/triangulation.h"

#include <gtest/gtest.h>

#include <random>

#include "processing/geometry/intersection.h"
#include "tests/common/paper_rig.h"

namespace ts {
namespace {

class Triangulation : public ::testing::Test {
 protected:
  StereoRig rig_ = testing::RealisticRig();
  Rectification r_ = Rectify(rig_);

  StereoMatch MatchOf(const Eigen::Vector3d& p_left, double sigma_d) const {
    StereoMatch m;
    m.left_px = r_.LeftPixel(p_left);
    m.right_px = r_.RightPixel(p_left);
    m.disparity_px = m.left_px.x() - m.right_px.x();
    m.sigma_disparity_px = sigma_d;
    m.correlation = 0.93;
    return m;
  }
};

TEST_F(Triangulation, RecoversKnownPoints) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> lateral(-10, 10), depth(2, 60);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p(lateral(rng), 0.3 * lateral(rng), depth(rng));
    Eigen::Vector3d q;
    Eigen::Matrix3d c;
    ASSERT_TRUE(TriangulateRectified(r_, MatchOf(p, 0.1), &q, &c));
    EXPECT_LT((r_.left_from_rect * q - p).norm(), 1e-9 * p.norm());
  }
  StereoMatch behind = MatchOf({0, 0, 10}, 0.1);
  behind.disparity_px = 0.0;
  Eigen::Vector3d q;
  Eigen::Matrix3d c;
  EXPECT_FALSE(TriangulateRectified(r_, behind, &q, &c));
}

// The normal-case formula is the two-ray intersection: same point, and the same range
// sigma as intersection.h gives for the right ray's uncertainty (left ray exact).
TEST_F(Triangulation, AgreesWithTheGeneralIntersection) {
  const CameraModel left(rig_.left), right(rig_.right);
  const Eigen::Vector3d right_centre = r_.left_from_rect * Eigen::Vector3d(r_.baseline_m, 0, 0);
  Eigen::Isometry3d left_from_right = Eigen::Isometry3d::Identity();
  left_from_right.linear() = rig_.left_from_right;
  left_from_right.translation() = right_centre;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.0, 1.2, 4.0), Eigen::Vector3d(-3.0, 0.8, 15.0),
                                   Eigen::Vector3d(6.0, 0.5, 35.0)}) {
    const double sigma_d = 0.1;
    Eigen::Vector3d q;
    Eigen::Matrix3d c;
    ASSERT_TRUE(TriangulateRectified(r_, MatchOf(p, sigma_d), &q, &c));
    std::vector<RayObservation> rays(2);
    rays[0].camera = &left;
    ASSERT_TRUE(left.Project(p, &rays[0].pixel));
    rays[0].sigma_px = 1e-4;
    rays[1].camera = &right;
    rays[1].world_from_camera = left_from_right;
    ASSERT_TRUE(right.Project(left_from_right.inverse() * p, &rays[1].pixel));
    rays[1].sigma_px = sigma_d;
    const IntersectionResult general = IntersectRays(rays);
    ASSERT_TRUE(general.usable) << general.why;
    EXPECT_LT((general.point_world - r_.left_from_rect * q).norm(), 1e-6);
    const Eigen::Vector3d along = p.normalized();
    const Eigen::Matrix3d c_left = r_.left_from_rect * c * r_.left_from_rect.transpose();
    const double sigma_range = std::sqrt(along.dot(c_left * along));
    const double sigma_general = std::sqrt(along.dot(general.covariance_m2 * along));
    // Distortion and the rectified focal length change the local pixel scale by a few %.
    EXPECT_NEAR(sigma_range / sigma_general, 1.0, 0.05) << p.transpose();
    // Normal case: sigma_Z = Z^2 / (f B) sigma_d.
    const double z = q.z();
    EXPECT_NEAR(std::sqrt(c(2, 2)), z * z / (r_.focal_px * r_.baseline_m) * sigma_d, 1e-9 * z);
  }
}

TEST_F(Triangulation, PairPointsAreTakenIntoTheStationFrame) {
  Eigen::Isometry3d l_from_left = Eigen::Isometry3d::Identity();
  l_from_left.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -0.4, 1).normalized()).toRotationMatrix();
  l_from_left.translation() = Eigen::Vector3d(0.25, -0.1, 0.05);
  const Eigen::Vector3d p(2.0, 1.0, 12.0);
  PointCloud cloud;
  AppendPairPoints(r_, {MatchOf(p, 0.2)}, l_from_left, 7, &cloud);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_LT((cloud[0].position_m - l_from_left * p).norm(), 1e-9);
  EXPECT_EQ(cloud[0].pair, 7);
  EXPECT_FLOAT_EQ(cloud[0].correlation, 0.93f);
  EXPECT_FLOAT_EQ(cloud[0].sigma_disparity_px, 0.2f);
  // A rotation keeps the covariance's size; its long axis is the left ray.
  Eigen::Vector3d q;
  Eigen::Matrix3d c;
  TriangulateRectified(r_, MatchOf(p, 0.2), &q, &c);
  EXPECT_NEAR(cloud[0].covariance_m2.trace(), c.trace(), 1e-5 * c.trace());
  const Eigen::Vector3d ray_l = (l_from_left.linear() * p).normalized();
  EXPECT_NEAR(ray_l.dot(cloud[0].covariance_m2.cast<double>() * ray_l), c.trace(),
              1e-4 * c.trace());
}

}  // namespace
}  // namespace ts
