#include "processing/geometry/stereo_rig.h"

#include <gtest/gtest.h>

#include "processing/geometry/rotation.h"
#include "tests/common/paper_rig.h"

namespace ts {
namespace {

StereoRig Skewed() {
  StereoRig rig;
  rig.left = rig.right = testing::PaperCamera();
  rig.baseline_m = 0.5;
  rig.S_from_left = StereoRig::NominalSFromCamera() * RotationFromOpk({0.01, -0.02, 0.005});
  rig.left_from_right = RotationFromOpk({-0.003, 0.015, 0.002});
  return rig;
}

TEST(StereoRig, Seed003Equation2) {
  const StereoRig rig = Skewed();
  const Eigen::Isometry3d l = rig.SFromLeftCamera(), r = rig.SFromRightCamera();
  EXPECT_TRUE(r.translation().isApprox(-l.translation()));             // T_r = -T_l
  EXPECT_TRUE(r.linear().isApprox(l.linear() * rig.left_from_right));  // R_r = R_l R
  EXPECT_TRUE(l.translation().isApprox(Eigen::Vector3d(-0.25, 0, 0)));
}

TEST(StereoRig, NominalCameraLooksForwardWithRowsHorizontal) {
  const Eigen::Matrix3d r = StereoRig::NominalSFromCamera();
  EXPECT_TRUE((r * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE((r * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitX()));
  EXPECT_TRUE((r * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
}

TEST(StereoRig, RecoversRigFromOpenCvStereoCalibration) {
  const StereoRig truth = Skewed();
  // OpenCV convention: p_right = R p_left + t.
  const Eigen::Isometry3d right_from_left = truth.RightFromLeftCamera();
  const StereoRig rig = StereoRig::FromStereoCalibration(
      truth.left, truth.right, right_from_left.linear(), right_from_left.translation());
  EXPECT_NEAR(rig.baseline_m, 0.5, 1e-12);
  EXPECT_TRUE(rig.left_from_right.isApprox(truth.left_from_right, 1e-12));
  // The relative pose must be reproduced exactly whatever S is chosen.
  const Eigen::Isometry3d again = rig.RightFromLeftCamera();
  EXPECT_TRUE(again.matrix().isApprox(right_from_left.matrix(), 1e-12));
  // X of S along the baseline, Y close to the viewing directions.
  const Eigen::Vector3d view = rig.S_from_left * Eigen::Vector3d::UnitZ();
  EXPECT_GT(view.y(), 0.99);
  std::string why;
  EXPECT_TRUE(rig.Check(&why)) << why;
}

TEST(StereoRig, CheckRejectsBadRig) {
  std::string why;
  StereoRig rig = Skewed();
  rig.baseline_m = 0;
  EXPECT_FALSE(rig.Check(&why));
  rig = Skewed();
  rig.left_from_right(0, 0) = 2.0;
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("left_from_right"), std::string::npos);
  rig = Skewed();
  rig.right.principal_distance_px = -1;
  EXPECT_FALSE(rig.Check(&why));
  EXPECT_NE(why.find("right camera"), std::string::npos);
}

}  // namespace
}  // namespace ts
