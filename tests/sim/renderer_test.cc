// The renderer against independent answers: ranges from a plain ray march of the terrain
// function, and left/right images that agree where the true geometry says they must.
#include "sim/renderer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim_station.h"
#include "tests/common/terrain_march.h"

namespace ts::sim {
namespace {

using testing::MarchToTerrain;

class RendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    SimStationOptions options;
    options.scene = "hills";
    options.seed = 3;
    station_ = *BuildSimStation(options);
  }
  static std::shared_ptr<const SimStation> station_;
};
std::shared_ptr<const SimStation> RendererTest::station_;

TEST_F(RendererTest, RangeImageMatchesAnIndependentRayMarch) {
  const Calibration& cal = station_->rig.truth;
  const CameraModel camera(cal.rig.left);
  const Eigen::Isometry3d pose = cal.LFromCamera(Side::kLeft, 40.0, -16.0);
  Renderer renderer(station_->scene, station_->mesh);
  cv::Mat range;
  renderer.Render(camera, pose, {}, &range);
  int compared = 0;
  for (int y = 100; y < 1040; y += 113) {
    for (int x = 7; x < 1392; x += 131) {
      const Eigen::Vector3d ray = pose.linear() * camera.RayFromPixel({x, y});
      const double expected = MarchToTerrain(station_->scene, pose.translation(), ray);
      const float got = range.at<float>(y, x);
      if (std::isnan(expected)) continue;
      ASSERT_FALSE(std::isnan(got)) << x << "," << y;
      // The march steps 2 cm and may skip a thin crest; compare where it is unambiguous.
      if (std::abs(got - expected) < 0.05 * expected) {
        EXPECT_NEAR(got, expected, 1e-6 * expected + 1e-6) << x << "," << y;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 60);
}

// A ground point seen by both cameras: the two images must show the same texture there.
double Ncc(const cv::Mat& a, const cv::Mat& b) {
  cv::Scalar ma, sa, mb, sb;
  cv::meanStdDev(a, ma, sa);
  cv::meanStdDev(b, mb, sb);
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F, 1.0, -ma[0]);
  b.convertTo(fb, CV_64F, 1.0, -mb[0]);
  return fa.dot(fb) / (fa.total() * sa[0] * sb[0]);
}

TEST_F(RendererTest, LeftAndRightAgreeOnTrueCorrespondences) {
  const Calibration& cal = station_->rig.truth;
  const double pan = 200.0, tilt = -17.0;
  Renderer renderer(station_->scene, station_->mesh);
  cv::Mat images[2];
  for (Side side : {Side::kLeft, Side::kRight}) {
    FrameRequest r;
    r.side = side;
    r.pan_deg = pan;
    r.tilt_deg = tilt;
    images[side == Side::kLeft ? 0 : 1] = RenderFrame(renderer, *station_, r);
  }
  const CameraModel left(cal.rig.left), right(cal.rig.right);
  const Eigen::Isometry3d l_pose = cal.LFromCamera(Side::kLeft, pan, tilt);
  const Eigen::Isometry3d r_pose = cal.LFromCamera(Side::kRight, pan, tilt);
  int good = 0, total = 0;
  for (int y = 400; y < 1000; y += 60) {
    for (int x = 200; x < 1200; x += 100) {
      const Eigen::Vector3d ray = l_pose.linear() * left.RayFromPixel({x, y});
      const double t = MarchToTerrain(station_->scene, l_pose.translation(), ray);
      if (std::isnan(t)) continue;
      Eigen::Vector2d in_right;
      if (!right.Project(r_pose.inverse() * (l_pose.translation() + t * ray), &in_right)) continue;
      const int rx = static_cast<int>(std::lround(in_right.x()));
      const int ry = static_cast<int>(std::lround(in_right.y()));
      if (rx < 20 || ry < 20 || rx >= 1372 || ry >= 1020) continue;
      const cv::Rect a(x - 7, y - 7, 15, 15), b(rx - 7, ry - 7, 15, 15);
      ++total;
      good += Ncc(images[0](a), images[1](b)) > 0.8;
    }
  }
  ASSERT_GT(total, 40);
  EXPECT_GT(static_cast<double>(good) / total, 0.9) << good << " of " << total;
}

TEST_F(RendererTest, SameRequestSameImage) {
  Renderer a(station_->scene, station_->mesh), b(station_->scene, station_->mesh);
  FrameRequest r;
  r.pan_deg = 10.0;
  r.tilt_deg = -15.0;
  r.render.supersampling = 1;
  const cv::Mat x = RenderFrame(a, *station_, r), y = RenderFrame(b, *station_, r);
  EXPECT_EQ(cv::norm(x, y, cv::NORM_INF), 0.0);
  r.pan_deg = 10.01;
  EXPECT_GT(cv::norm(x, RenderFrame(a, *station_, r), cv::NORM_L1), 0.0);
}

}  // namespace
}  // namespace ts::sim
