#include "processing/io/opencv_calibration_file.h"

#include <filesystem>
#include <opencv2/core/persistence.hpp>

#include "processing/io/atomic_file.h"

namespace ts {
namespace {

// FileStorage writes where it is told; the file appears whole or not at all.
Status WriteStorage(const std::string& file, const std::function<void(cv::FileStorage&)>& write) {
  try {
    cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
    write(fs);
    return WriteFileAtomically(file, fs.releaseAndGetString());
  } catch (const cv::Exception& e) {
    return Error{file + ": " + e.msg};
  }
}

cv::Mat Matrix(const cv::FileStorage& fs, const std::string& file,
               std::initializer_list<const char*> names) {
  for (const char* name : names) {
    cv::Mat m;
    if (fs[name].empty()) continue;
    fs[name] >> m;
    if (m.empty()) throw std::runtime_error(file + ": " + name + ": not a matrix");
    m.convertTo(m, CV_64F);
    return m;
  }
  throw std::runtime_error(file + ": " + *names.begin() + ": missing");
}

int ImageSize(const cv::FileStorage& fs, const std::string& file, const char* name, int index) {
  if (!fs[name].empty()) return static_cast<int>(fs[name]);
  if (!fs["imageSize"].empty()) return static_cast<int>(fs["imageSize"][index]);
  throw std::runtime_error(file + ": " + name + ": missing (the image size is needed)");
}

CameraIntrinsics Convert(const cv::FileStorage& fs, const std::string& file, const char* k,
                         const char* k_short, const char* d, const char* d_short,
                         ModelConversion* conversion) {
  const OpenCvCamera camera{ImageSize(fs, file, "image_width", 0),
                            ImageSize(fs, file, "image_height", 1), Matrix(fs, file, {k, k_short}),
                            Matrix(fs, file, {d, d_short})};
  if (camera.width_px <= 0 || camera.height_px <= 0)
    throw std::runtime_error(file + ": image_width, image_height: must be positive");
  const Result<CameraIntrinsics> ours = FromOpenCv(camera, conversion);
  if (!ours) throw std::runtime_error(file + ": " + ours.error());
  return *ours;
}

cv::FileStorage Open(const std::string& file) {
  if (!std::filesystem::is_regular_file(file))
    throw std::runtime_error(file + ": cannot read file");
  try {
    cv::FileStorage fs(file, cv::FileStorage::READ);
    if (fs.isOpened()) return fs;
  } catch (const cv::Exception& e) {
    throw std::runtime_error(file + ": not an OpenCV FileStorage file (" + e.err + ")");
  }
  throw std::runtime_error(file + ": not an OpenCV FileStorage file");
}

}  // namespace

Status SaveOpenCvCamera(const CameraIntrinsics& camera, const std::string& file,
                        ModelConversion* conversion) {
  const Result<OpenCvCamera> opencv = ToOpenCv(camera, conversion);
  if (!opencv) return Error{file + ": " + opencv.error()};
  return WriteStorage(file, [&](cv::FileStorage& fs) {
    fs << "image_width" << opencv->width_px << "image_height" << opencv->height_px;
    fs << "cameraMatrix" << opencv->camera_matrix << "distCoeffs" << opencv->dist_coeffs;
  });
}

Status SaveOpenCvStereo(const Calibration& calibration, const std::string& file,
                        OpenCvExport* conversion) {
  const StereoRig& rig = calibration.rig;
  const Result<OpenCvCamera> left = ToOpenCv(rig.left, &conversion->left);
  if (!left) return Error{file + ": left camera: " + left.error()};
  const Result<OpenCvCamera> right = ToOpenCv(rig.right, &conversion->right);
  if (!right) return Error{file + ": right camera: " + right.error()};
  const Eigen::Isometry3d right_from_left = rig.RightFromLeftCamera();
  cv::Mat r(3, 3, CV_64F), t(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) {
    t.at<double>(i) = right_from_left.translation()[i];
    for (int j = 0; j < 3; ++j) r.at<double>(i, j) = right_from_left.linear()(i, j);
  }
  return WriteStorage(file, [&](cv::FileStorage& fs) {
    fs << "image_width" << left->width_px << "image_height" << left->height_px;
    fs << "cameraMatrix1" << left->camera_matrix << "distCoeffs1" << left->dist_coeffs;
    fs << "cameraMatrix2" << right->camera_matrix << "distCoeffs2" << right->dist_coeffs;
    fs << "R" << r << "T" << t;
  });
}

Result<Calibration> LoadOpenCvStereo(const std::string& file, OpenCvExport* conversion) {
  try {
    const cv::FileStorage fs = Open(file);
    const CameraIntrinsics left =
        Convert(fs, file, "cameraMatrix1", "M1", "distCoeffs1", "D1", &conversion->left);
    const CameraIntrinsics right =
        Convert(fs, file, "cameraMatrix2", "M2", "distCoeffs2", "D2", &conversion->right);
    const cv::Mat r = Matrix(fs, file, {"R"}), t = Matrix(fs, file, {"T"});
    if (r.rows != 3 || r.cols != 3) throw std::runtime_error(file + ": R: must be 3 x 3");
    if (t.total() != 3) throw std::runtime_error(file + ": T: must hold 3 numbers");
    Eigen::Matrix3d rotation;
    Eigen::Vector3d translation;
    for (int i = 0; i < 3; ++i) {
      translation[i] = t.at<double>(i);
      for (int j = 0; j < 3; ++j) rotation(i, j) = r.at<double>(i, j);
    }
    if (!rotation.allFinite() || !translation.allFinite() ||
        (rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6)
      throw std::runtime_error(file + ": R: not a rotation");
    if (!(translation.norm() > 0.0)) throw std::runtime_error(file + ": T: must not be zero");
    Calibration cal;
    cal.rig = StereoRig::FromStereoCalibration(left, right, rotation, translation);
    std::string why;
    if (!cal.Check(&why)) throw std::runtime_error(file + ": " + why);
    return cal;
  } catch (const std::exception& e) {
    return Error{e.what()};
  }
}

Result<CameraIntrinsics> LoadOpenCvCamera(const std::string& file, ModelConversion* conversion) {
  try {
    const cv::FileStorage fs = Open(file);
    return Convert(fs, file, "cameraMatrix", "M", "distCoeffs", "D", conversion);
  } catch (const std::exception& e) {
    return Error{e.what()};
  }
}

}  // namespace ts
