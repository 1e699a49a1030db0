// OpenCV FileStorage calibrations: a stereo calibration written for OpenCV projects every
// point alike through cv::projectPoints with the file's R and T, reads back to the same rig,
// and bad files are one clear error naming file and field.
#include "processing/io/opencv_calibration_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/calib3d.hpp>

#include "processing/geometry/rotation.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

Calibration Rig() {
  Calibration cal;
  CameraIntrinsics c;
  c.width_px = 1392;
  c.height_px = 1040;
  c.principal_distance_px = 1861.0;
  c.principal_point_x_px = 700.0;
  c.principal_point_y_px = 515.0;
  c.k1 = -0.08;
  c.k2 = 0.05;
  c.p1 = 1e-4;
  c.scale_x = 2e-4;
  cal.rig.left = c;
  c.principal_distance_px = 1858.0;
  c.k1 = -0.07;
  cal.rig.right = c;
  cal.rig.baseline_m = 0.5;
  cal.rig.left_from_right = RotationFromOpk({0.001, -0.02, 0.004});
  return cal;
}

// Points 5-30 m in front of the left camera, over both frames.
std::vector<Eigen::Vector3d> Points() {
  std::vector<Eigen::Vector3d> points;
  for (double z : {5.0, 30.0})
    for (int j = -4; j <= 4; ++j)
      for (int i = -5; i <= 5; ++i) points.emplace_back(0.07 * i * z, 0.07 * j * z, z);
  return points;
}

double MaxDifferencePx(const CameraIntrinsics& ours, const Eigen::Isometry3d& camera_from_left,
                       const cv::Mat& k, const cv::Mat& d, const cv::Mat& r, const cv::Mat& t) {
  std::vector<cv::Point3d> object;
  for (const Eigen::Vector3d& p : Points()) object.emplace_back(p.x(), p.y(), p.z());
  cv::Mat rvec;
  cv::Rodrigues(r, rvec);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, rvec, t, k, d, projected);
  const CameraModel model(ours);
  double worst = 0.0;
  for (size_t i = 0; i < object.size(); ++i) {
    Eigen::Vector2d pixel;
    if (!model.Project(camera_from_left * Points()[i], &pixel) || !model.InImage(pixel)) continue;
    worst = std::max(worst, (pixel - Eigen::Vector2d(projected[i].x, projected[i].y)).norm());
  }
  return worst;
}

TEST(OpenCvCalibrationFile, StereoExportProjectsAlikeInOpenCvAndReadsBack) {
  testing::TempDir dir;
  const Calibration cal = Rig();
  OpenCvExport conversion;
  ASSERT_TRUE(SaveOpenCvStereo(cal, dir / "stereo.yml", &conversion).ok());
  cv::FileStorage fs(dir / "stereo.yml", cv::FileStorage::READ);
  cv::Mat k1, d1, k2, d2, r, t;
  fs["cameraMatrix1"] >> k1;
  fs["distCoeffs1"] >> d1;
  fs["cameraMatrix2"] >> k2;
  fs["distCoeffs2"] >> d2;
  fs["R"] >> r;
  fs["T"] >> t;
  EXPECT_NEAR(cv::norm(t), 0.5, 1e-12);
  const Eigen::Isometry3d right_from_left = cal.rig.RightFromLeftCamera();
  const double left = MaxDifferencePx(cal.rig.left, Eigen::Isometry3d::Identity(), k1, d1,
                                      cv::Mat::eye(3, 3, CV_64F), cv::Mat::zeros(3, 1, CV_64F));
  const double right = MaxDifferencePx(cal.rig.right, right_from_left, k2, d2, r, t);
  std::printf("OpenCV projects the left frame within %.5f px, the right within %.5f px\n", left,
              right);
  EXPECT_LE(left, 0.01);
  EXPECT_LE(right, 0.01);

  const Result<Calibration> back = LoadOpenCvStereo(dir / "stereo.yml", &conversion);
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_NEAR(back->rig.baseline_m, 0.5, 1e-12);
  EXPECT_TRUE(back->rig.left_from_right.isApprox(cal.rig.left_from_right, 1e-12));
  EXPECT_LE(conversion.left.max_difference_px, 0.01);
  EXPECT_NEAR(back->rig.left.principal_distance_px, 1861.0, 0.05);
}

TEST(OpenCvCalibrationFile, BadFilesAreOneClearErrorNamingFileAndField) {
  testing::TempDir dir;
  const Calibration cal = Rig();
  OpenCvExport conversion;
  ASSERT_TRUE(SaveOpenCvStereo(cal, dir / "good.yml", &conversion).ok());
  std::ifstream in(dir / "good.yml");
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const struct {
    std::string text, expect;
  } cases[] = {
      {good.substr(0, good.find("T:")), "T: missing"},
      {"%YAML:1.0\n---\nimage_width: 10\nimage_height: 10\n", "cameraMatrix1: missing"},
      {"%YAML:1.0\n---\nimage_width: 10\n", "image_height: missing"},
      {"not: [a, storage", "not an OpenCV FileStorage file"},
  };
  for (const auto& c : cases) {
    const std::string file = dir / "bad.yml";
    std::ofstream(file) << c.text;
    const Result<Calibration> r = LoadOpenCvStereo(file, &conversion);
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_EQ(r.error().rfind(file + ": ", 0), 0u) << r.error();
    EXPECT_NE(r.error().find(c.expect), std::string::npos) << r.error();
  }
  EXPECT_NE(LoadOpenCvStereo(dir / "none.yml", &conversion).error().find("cannot read"),
            std::string::npos);
}

}  // namespace
}  // namespace ts
