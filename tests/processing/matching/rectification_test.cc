#include "processing/matching/rectification.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>
#include <random>

#include "processing/geometry/rotation.h"
#include "tests/common/paper_rig.h"

namespace ts {
namespace {

TEST(Rectification, ConjugatePointsShareARowAndDisparityGivesDepth) {
  const StereoRig rig = testing::RealisticRig();
  const Rectification r = Rectify(rig);
  EXPECT_NEAR(r.baseline_m, 0.5, 1e-12);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> lateral(-8, 8), depth(3, 50);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(lateral(rng), 0.4 * lateral(rng), depth(rng));  // left frame
    const Eigen::Vector2d l = r.LeftPixel(p), rr = r.RightPixel(p);
    EXPECT_NEAR(l.y(), rr.y(), 1e-9);
    const double z_rect = (r.left_from_rect.transpose() * p).z();
    EXPECT_NEAR(r.DepthFromDisparity(l.x() - rr.x()), z_rect, 1e-9 * z_rect);
  }
}

// The maps send every rectified pixel to where the original (distorted) camera saw the same
// ray: checked by projecting 3D points both ways.
TEST(Rectification, MapsPointIntoTheOriginalImagesWithDistortion) {
  const StereoRig rig = testing::RealisticRig();
  const Rectification r = Rectify(rig);
  const CameraModel left(rig.left), right(rig.right);
  const Eigen::Isometry3d right_from_left = rig.RightFromLeftCamera();
  int checked = 0;
  for (double x : {-5.0, -1.0, 2.0, 6.0}) {
    for (double y : {-2.0, 0.5, 3.0}) {
      const Eigen::Vector3d p(x, y, 20.0);
      const Eigen::Vector2d lr = r.LeftPixel(p), rr = r.RightPixel(p);
      for (const auto& [rect, camera, point, mx, my] :
           {std::tuple{lr, &left, p, &r.left_map_x, &r.left_map_y},
            std::tuple{rr, &right, Eigen::Vector3d(right_from_left * p), &r.right_map_x,
                       &r.right_map_y}}) {
        const int u = static_cast<int>(std::lround(rect.x()));
        const int v = static_cast<int>(std::lround(rect.y()));
        if (u < 1 || v < 1 || u >= r.width_px - 1 || v >= r.height_px - 1) continue;
        // The map at the rounded rectified pixel vs the projection of that pixel's ray.
        const Eigen::Matrix3d camera_from_rect =
            camera == &left ? r.left_from_rect : r.right_from_rect;
        const Eigen::Vector3d ray(u - r.principal_point_px.x(), v - r.principal_point_px.y(),
                                  r.focal_px);
        Eigen::Vector2d expected;
        ASSERT_TRUE(camera->Project(camera_from_rect * ray, &expected));
        EXPECT_NEAR(mx->at<float>(v, u), expected.x(), 1e-3);
        EXPECT_NEAR(my->at<float>(v, u), expected.y(), 1e-3);
        // And the point itself: its measured pixel is where the map sends its rectified pixel.
        Eigen::Vector2d measured;
        ASSERT_TRUE(camera->Project(point, &measured));
        const double du = rect.x() - u, dv = rect.y() - v;
        const double map_x = mx->at<float>(v, u) +
                             du * (mx->at<float>(v, u + 1) - mx->at<float>(v, u)) +
                             dv * (mx->at<float>(v + 1, u) - mx->at<float>(v, u));
        EXPECT_NEAR(map_x, measured.x(), 0.01);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 15);
}

// The maps are interpolated between exact nodes: everywhere within a thousandth of a pixel of
// the exact projection (checked on a grid that misses the nodes).
TEST(Rectification, InterpolatedMapsMatchTheExactProjectionEverywhere) {
  const StereoRig rig = testing::RealisticRig();
  const Rectification r = Rectify(rig);
  const CameraModel left(rig.left);
  double worst = 0.0;
  for (int v = 3; v < r.height_px; v += 7)
    for (int u = 5; u < r.width_px; u += 7) {
      const Eigen::Vector3d ray(u - r.principal_point_px.x(), v - r.principal_point_px.y(),
                                r.focal_px);
      Eigen::Vector2d exact;
      ASSERT_TRUE(left.Project(r.left_from_rect * ray, &exact));
      worst = std::max({worst, std::abs(r.left_map_x.at<float>(v, u) - exact.x()),
                        std::abs(r.left_map_y.at<float>(v, u) - exact.y())});
    }
  EXPECT_LT(worst, 1e-3);
}

TEST(Rectification, RectifiedImagesAlignRows) {
  // A horizontal line of bright dots at 30 m in front of the rig: after rectification each
  // dot is on the same row in both images.
  const StereoRig rig = testing::RealisticRig();
  const Rectification r = Rectify(rig);
  const CameraModel left(rig.left), right(rig.right);
  const Eigen::Isometry3d right_from_left = rig.RightFromLeftCamera();
  cv::Mat li(1040, 1392, CV_32FC1, cv::Scalar(0)), ri = li.clone();
  const Eigen::Vector3d p(1.0, 0.8, 30.0);
  Eigen::Vector2d lp, rp;
  ASSERT_TRUE(left.Project(p, &lp));
  ASSERT_TRUE(right.Project(right_from_left * p, &rp));
  cv::circle(li, {int(std::lround(lp.x())), int(std::lround(lp.y()))}, 3, 255, cv::FILLED);
  cv::circle(ri, {int(std::lround(rp.x())), int(std::lround(rp.y()))}, 3, 255, cv::FILLED);
  cv::Mat lr, rr;
  RectifyPair(r, li, ri, &lr, &rr);
  const cv::Moments ml = cv::moments(lr), mr = cv::moments(rr);
  EXPECT_NEAR(ml.m01 / ml.m00, mr.m01 / mr.m00, 0.6);  // rows agree (dots drawn to 1 px)
}

}  // namespace
}  // namespace ts
