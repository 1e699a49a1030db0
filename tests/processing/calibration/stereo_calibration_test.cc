// The joint stereo adjustment against OpenCV's stereoCalibrate on the same detections of the
// real stereo chessboard set (../shared/data/calibration/opencv_stereo_chessboard/), and
// against a synthetic rig whose relative orientation is known.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "processing/calibration/camera_calibration.h"
#include "processing/calibration/chessboard.h"
#include "processing/geometry/rotation.h"
#include "tests/common/opencv_sample_boards.h"

namespace ts {
namespace {

struct OpenCvStereo {
  double rms = 0.0;
  cv::Mat k1, k2, r, t;
};

// stereoCalibrate as OpenCV's stereo_calib.cpp sample runs it, and with the default model
// refined jointly from calibrateCamera's; the better of the two is the reference.
OpenCvStereo OpenCvStereoCalibrate(const TargetViews& left, const TargetViews& right) {
  const OpenCvCorners left_corners = ToOpenCvCorners(left);
  const std::vector<std::vector<cv::Point3f>>& object = left_corners.object;
  const std::vector<std::vector<cv::Point2f>>& l = left_corners.image;
  const std::vector<std::vector<cv::Point2f>> r = ToOpenCvCorners(right).image;
  const cv::Size size(left.width_px, left.height_px);
  OpenCvStereo sample;
  sample.k1 = cv::initCameraMatrix2D(object, l, size, 0);
  sample.k2 = cv::initCameraMatrix2D(object, r, size, 0);
  cv::Mat d1, d2, e, f;
  sample.rms = cv::stereoCalibrate(
      object, l, r, sample.k1, d1, sample.k2, d2, size, sample.r, sample.t, e, f,
      cv::CALIB_FIX_ASPECT_RATIO | cv::CALIB_ZERO_TANGENT_DIST | cv::CALIB_USE_INTRINSIC_GUESS |
          cv::CALIB_SAME_FOCAL_LENGTH | cv::CALIB_RATIONAL_MODEL | cv::CALIB_FIX_K3 |
          cv::CALIB_FIX_K4 | cv::CALIB_FIX_K5,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-5));
  OpenCvStereo joint;
  cv::Mat j1, j2;
  std::vector<cv::Mat> rv, tv;
  cv::calibrateCamera(object, l, size, joint.k1, j1, rv, tv);
  cv::calibrateCamera(object, r, size, joint.k2, j2, rv, tv);
  joint.rms = cv::stereoCalibrate(object, l, r, joint.k1, j1, joint.k2, j2, size, joint.r, joint.t,
                                  e, f, cv::CALIB_USE_INTRINSIC_GUESS);
  std::printf("OpenCV stereoCalibrate: sample flags RMS %.4f px, default model %.4f px\n",
              sample.rms, joint.rms);
  return sample.rms < joint.rms ? sample : joint;
}

// Target of issue 20: stereo RMS no worse than stereoCalibrate's by more than 2 %, focal
// lengths within 0.5 %, and the same relative orientation.
TEST(StereoCalibration, RealPairsMatchOpenCvStereoCalibrateOnTheSameCorners) {
  TargetViews left, right;
  DetectSamplePairs(&left, &right);
  ASSERT_GE(left.views.size(), 12u);
  const OpenCvStereo opencv = OpenCvStereoCalibrate(left, right);
  const Result<StereoCalibration> ours = CalibrateStereo(left, right, {});
  ASSERT_TRUE(ours.ok()) << ours.error();
  std::printf(
      "ours: RMS %.4f px (left %.4f, right %.4f), baseline %.4f +- %.4f squares (OpenCV %.4f), "
      "angles %.3f %.3f %.3f +- %.3f %.3f %.3f deg, %d rejected\n",
      ours->rms_px, ours->left.rms_px, ours->right.rms_px, ours->baseline, ours->baseline_sigma,
      cv::norm(opencv.t), ours->angles_deg.x(), ours->angles_deg.y(), ours->angles_deg.z(),
      ours->angles_sigma_deg.x(), ours->angles_sigma_deg.y(), ours->angles_sigma_deg.z(),
      ours->rejected);
  EXPECT_LE(ours->rms_px, 1.02 * opencv.rms);
  EXPECT_NEAR(ours->left.fx() / opencv.k1.at<double>(0, 0), 1.0, 0.005);
  EXPECT_NEAR(ours->right.fy() / opencv.k2.at<double>(1, 1), 1.0, 0.005);
  // The relative orientation agrees within a few of its own sigmas.
  EXPECT_NEAR(ours->baseline, cv::norm(opencv.t), 4.0 * ours->baseline_sigma + 0.01);
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = opencv.r.at<double>(i, j);
  const Eigen::AngleAxisd difference(ours->right_from_left.linear() * r.transpose());
  EXPECT_LT(DegFromRad(difference.angle()), 4.0 * ours->angles_sigma_deg.maxCoeff() + 0.05);
  EXPECT_GT(ours->baseline_sigma, 0.0);
}

// A synthetic rig (0.5 m baseline, a small convergence and roll): 12 board placements seen by
// both cameras, corners with 0.1 px of noise. The relative orientation within 4 sigma.
TEST(StereoCalibration, RecoversAKnownRelativeOrientation) {
  CameraIntrinsics camera;
  camera.width_px = 1392;
  camera.height_px = 1040;
  camera.principal_distance_px = 1860.0;
  camera.principal_point_x_px = 690.0;
  camera.principal_point_y_px = 525.0;
  camera.k1 = -0.08;
  camera.k2 = 0.05;
  CameraIntrinsics other = camera;
  other.principal_distance_px = 1866.0;
  other.k1 = -0.07;
  Eigen::Isometry3d right_from_left = Eigen::Isometry3d::Identity();
  right_from_left.linear() =
      RotationFromOpk({RadFromDeg(0.3), RadFromDeg(-1.2), RadFromDeg(0.2)}).transpose();
  right_from_left.translation() = right_from_left.linear() * Eigen::Vector3d(-0.5, 0.002, 0.01);
  ChessboardOptions board;
  board.columns = 12;
  board.rows = 8;
  board.square = 0.1;
  TargetViews left, right;
  for (TargetViews* side : {&left, &right}) {
    side->target = ChessboardCorners(board);
    side->width_px = camera.width_px;
    side->height_px = camera.height_px;
  }
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const CameraModel left_model(camera), right_model(other);
  for (int placement = 0; left.views.size() < 12; ++placement) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(0.5 * u(rng), Eigen::Vector3d::UnitX()) *
                     Eigen::AngleAxisd(0.5 * u(rng), Eigen::Vector3d::UnitY()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.25 * u(rng) - 0.3, 0.2 * u(rng) - 0.35, 3.0 + u(rng));
    std::vector<Eigen::Vector2d> lp, rp;
    for (const Eigen::Vector3d& p : left.target) {
      Eigen::Vector2d a, b;
      if (!left_model.Project(pose * p, &a) || !left_model.InImage(a) ||
          !right_model.Project(right_from_left * pose * p, &b) || !right_model.InImage(b))
        break;
      lp.push_back(a + Eigen::Vector2d(noise(rng), noise(rng)));
      rp.push_back(b + Eigen::Vector2d(noise(rng), noise(rng)));
    }
    if (lp.size() != left.target.size()) continue;
    char name[16];
    std::snprintf(name, sizeof(name), "%02d", placement);
    left.AddFullView(name, placement, lp);
    right.AddFullView(name, placement, rp);
  }
  CameraCalibrationOptions options;
  options.keep_all_terms = true;
  options.fix_k3 = options.fix_tangential = options.fix_scale_x = true;
  const Result<StereoCalibration> s = CalibrateStereo(left, right, options);
  ASSERT_TRUE(s.ok()) << s.error();
  const Opk truth = OpkFromRotation(right_from_left.linear().transpose());
  const Eigen::Vector3d truth_deg(DegFromRad(truth.omega_rad), DegFromRad(truth.phi_rad),
                                  DegFromRad(truth.kappa_rad));
  const double truth_baseline = right_from_left.inverse().translation().norm();
  EXPECT_NEAR(s->baseline, truth_baseline, 4.0 * s->baseline_sigma);
  for (int j = 0; j < 3; ++j)
    EXPECT_NEAR(s->angles_deg[j], truth_deg[j], 4.0 * s->angles_sigma_deg[j]) << j;
  EXPECT_NEAR(s->left.intrinsics.principal_distance_px, 1860.0, 4.0 * s->left.sigma[0]);
  EXPECT_NEAR(s->right.intrinsics.principal_distance_px, 1866.0, 4.0 * s->right.sigma[0]);
  EXPECT_NEAR(s->sigma0_px, 0.1, 0.015);
  // The rig the pipeline uses: the same baseline, the right camera where it was.
  const StereoRig rig = s->Rig(1.0);
  EXPECT_NEAR(rig.baseline_m, truth_baseline, 4.0 * s->baseline_sigma);
}

TEST(StereoCalibration, ViewsThatShareNoPlacementAreOneClearError) {
  TargetViews left, right;
  DetectSamplePairs(&left, &right);
  for (TargetView& v : right.views) v.placement += 100;
  const Result<StereoCalibration> s = CalibrateStereo(left, right, {});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("seen by both cameras"), std::string::npos) << s.error();
}

}  // namespace
}  // namespace ts
