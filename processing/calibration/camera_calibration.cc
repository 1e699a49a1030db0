#include "processing/calibration/camera_calibration.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace ts {
namespace {

constexpr int kN = CameraIntrinsics::kNumParameters;

// A target point's pixel in one view, in measured pixels: the point in the camera frame, its
// ideal reduced image coordinates i = c (X/Z, Y/Z), then the measured reduced r with
// r + d(r) = i (camera_model.h) by fixed-point iteration r <- i - d(r). It contracts by the
// derivative of d, about 0.5 at the corners of a strongly distorting lens: 40 steps leave
// far less than a micro-pixel.
struct TargetPointResidual {
  Eigen::Vector3d target;
  Eigen::Vector2d pixel;
  static constexpr int kIterations = 40;

  template <typename T>
  bool operator()(const T* intrinsics, const T* pose, T* residual) const {
    const T point[3] = {T(target.x()), T(target.y()), T(target.z())};
    T p[3];
    ceres::AngleAxisRotatePoint(pose, point, p);
    p[0] += pose[3], p[1] += pose[4], p[2] += pose[5];
    if (!(p[2] > T(0))) return false;
    const T ix = intrinsics[0] * p[0] / p[2], iy = intrinsics[0] * p[1] / p[2];
    T rx = ix, ry = iy;
    for (int k = 0; k < kIterations; ++k) {
      T dx, dy;
      DistortionCorrection(intrinsics, rx, ry, &dx, &dy);
      rx = ix - dx;
      ry = iy - dy;
    }
    residual[0] = intrinsics[1] + rx - T(pixel.x());
    residual[1] = intrinsics[2] + ry - T(pixel.y());
    // Far outside the lens's range the iteration diverges: a step there is refused.
    return ceres::isfinite(residual[0]) && ceres::isfinite(residual[1]);
  }
};

std::vector<int> FixedParameters(const CameraCalibrationOptions& o) {
  std::vector<int> fixed;
  for (const auto& [held, index] :
       {std::pair{o.fix_k3, 5}, std::pair{o.fix_tangential, 6}, std::pair{o.fix_tangential, 7},
        std::pair{o.fix_scale_x, 8}, std::pair{o.fix_shear, 9}})
    if (held) fixed.push_back(index);
  return fixed;
}

// Zhang's closed form for the pinhole terms, then each view's resection.
Status Initialise(const PlanarViews& views, int width_px, int height_px,
                  std::array<double, kN>* intrinsics, std::vector<std::array<double, 6>>* poses) {
  std::vector<std::vector<cv::Point3f>> object(views.pixels.size());
  std::vector<std::vector<cv::Point2f>> image(views.pixels.size());
  for (size_t v = 0; v < views.pixels.size(); ++v)
    for (size_t i = 0; i < views.target.size(); ++i) {
      object[v].emplace_back(views.target[i].x(), views.target[i].y(), views.target[i].z());
      image[v].emplace_back(views.pixels[v][i].x(), views.pixels[v][i].y());
    }
  const cv::Mat k = cv::initCameraMatrix2D(object, image, cv::Size(width_px, height_px), 1.0);
  const double f = k.at<double>(1, 1);
  if (!(f > 0.0) || !std::isfinite(f))
    return Error{"the views do not determine a focal length (are they all parallel?)"};
  intrinsics->fill(0.0);
  (*intrinsics)[0] = f;
  (*intrinsics)[1] = k.at<double>(0, 2);
  (*intrinsics)[2] = k.at<double>(1, 2);
  poses->resize(views.pixels.size());
  for (size_t v = 0; v < views.pixels.size(); ++v) {
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(object[v], image[v], k, cv::noArray(), rvec, tvec))
      return Error{"view " + views.names[v] + ": no resection"};
    for (int j = 0; j < 3; ++j) {
      (*poses)[v][j] = rvec.at<double>(j);
      (*poses)[v][3 + j] = tvec.at<double>(j);
    }
  }
  return {};
}

Status CheckViews(const PlanarViews& views) {
  if (views.pixels.size() < 3) return Error{"at least 3 views of the target are needed"};
  if (views.target.size() < 6) return Error{"at least 6 target points are needed"};
  if (views.names.size() != views.pixels.size()) return Error{"one name per view is needed"};
  for (size_t v = 0; v < views.pixels.size(); ++v) {
    if (views.pixels[v].size() != views.target.size())
      return Error{"view " + views.names[v] + ": one pixel per target point is needed"};
    for (const Eigen::Vector2d& p : views.pixels[v])
      if (!p.allFinite()) return Error{"view " + views.names[v] + ": a pixel is not finite"};
  }
  return {};
}

// sigma and correlations of the intrinsics from the adjustment's covariance, scaled by
// sigma0^2 (Ceres assumes unit-weight residuals).
bool EstimatePrecision(ceres::Problem* problem, double* intrinsics, CameraCalibration* result) {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks = {{intrinsics, intrinsics}};
  Eigen::Matrix<double, kN, kN, Eigen::RowMajor> c;
  if (!covariance.Compute(blocks, problem) ||
      !covariance.GetCovarianceBlock(intrinsics, intrinsics, c.data())) {
    result->sigma.fill(NAN);
    return false;
  }
  c *= result->sigma0_px * result->sigma0_px;
  for (int i = 0; i < kN; ++i) result->sigma[i] = std::sqrt(std::max(0.0, c(i, i)));
  for (int i = 0; i < kN; ++i)
    for (int j = 0; j < kN; ++j) {
      const double s = result->sigma[i] * result->sigma[j];
      result->correlation(i, j) = s > 0.0 ? c(i, j) / s : (i == j ? 1.0 : 0.0);
      if (j > i && std::abs(result->correlation(i, j)) > 0.9)
        result->high_correlations.push_back(std::string(CameraIntrinsics::kParameterNames[i]) +
                                            " / " + CameraIntrinsics::kParameterNames[j] + ": " +
                                            std::to_string(result->correlation(i, j)).substr(0, 5));
    }
  return true;
}

// RMS over all corners and per view, with the project's camera model (Newton projection).
void MeasureResiduals(const PlanarViews& views, const std::vector<std::array<double, 6>>& poses,
                      int free_parameters, CameraCalibration* result) {
  const CameraModel camera(result->intrinsics);
  double total = 0.0;
  for (size_t v = 0; v < views.pixels.size(); ++v) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    Eigen::Matrix3d rotation;  // column-major, as Ceres writes it
    ceres::AngleAxisToRotationMatrix(poses[v].data(), rotation.data());
    pose.linear() = rotation;
    pose.translation() = Eigen::Vector3d(poses[v][3], poses[v][4], poses[v][5]);
    result->camera_from_target.push_back(pose);
    double view = 0.0;
    for (size_t i = 0; i < views.target.size(); ++i) {
      Eigen::Vector2d pixel;
      const bool ok = camera.Project(pose * views.target[i], &pixel);
      const double e2 = ok ? (pixel - views.pixels[v][i]).squaredNorm() : 1e6;
      view += e2;
    }
    total += view;
    result->view_rms_px.push_back(std::sqrt(view / views.target.size()));
  }
  result->observations = static_cast<int>(views.pixels.size() * views.target.size());
  result->rms_px = std::sqrt(total / result->observations);
  const int redundancy = 2 * result->observations - free_parameters;
  result->sigma0_px = std::sqrt(total / std::max(1, redundancy));
}

}  // namespace

Result<CameraCalibration> CalibrateCamera(const PlanarViews& views, int width_px, int height_px,
                                          const CameraCalibrationOptions& o) {
  std::string why;
  if (!o.Check(&why)) return Error{"camera calibration: " + why};
  if (Status s = CheckViews(views); !s) return Error{"camera calibration: " + s.error()};
  std::array<double, kN> intrinsics;
  std::vector<std::array<double, 6>> poses;
  if (Status s = Initialise(views, width_px, height_px, &intrinsics, &poses); !s)
    return Error{"camera calibration: " + s.error()};

  ceres::Problem problem;
  for (size_t v = 0; v < views.pixels.size(); ++v)
    for (size_t i = 0; i < views.target.size(); ++i) {
      auto* cost = new ceres::AutoDiffCostFunction<TargetPointResidual, 2, kN, 6>(
          new TargetPointResidual{views.target[i], views.pixels[v][i]});
      ceres::LossFunction* loss = o.huber_px > 0.0 ? new ceres::HuberLoss(o.huber_px) : nullptr;
      problem.AddResidualBlock(cost, loss, intrinsics.data(), poses[v].data());
    }
  const std::vector<int> fixed = FixedParameters(o);
  if (!fixed.empty()) problem.SetManifold(intrinsics.data(), new ceres::SubsetManifold(kN, fixed));
  // Ceres reports through glog; what matters reaches the caller as a Result.
  FLAGS_minloglevel = google::GLOG_FATAL;
  ceres::Solver::Options solver;
  solver.logging_type = ceres::SILENT;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_num_iterations = o.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-12;
  solver.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  if (!summary.IsSolutionUsable())
    return Error{"camera calibration: the adjustment failed: " + summary.message};

  CameraCalibration result;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.intrinsics = CameraIntrinsics::FromParameters(intrinsics, width_px, height_px, 0.0);
  if (!result.intrinsics.Check(&why))
    return Error{"camera calibration: the adjustment ended in an invalid camera: " + why};
  const int free_parameters =
      kN - static_cast<int>(fixed.size()) + 6 * static_cast<int>(views.pixels.size());
  MeasureResiduals(views, poses, free_parameters, &result);
  if (result.sigma0_px > o.max_sigma0_ratio * o.corner_sigma_px) {
    const auto worst = std::max_element(result.view_rms_px.begin(), result.view_rms_px.end());
    return Error{"camera calibration: the adjustment does not fit the views (sigma0 " +
                 std::to_string(result.sigma0_px) + " px against corners good to " +
                 std::to_string(o.corner_sigma_px) + " px; worst view " +
                 views.names[worst - result.view_rms_px.begin()] + " at " + std::to_string(*worst) +
                 " px RMS): is the board size right?"};
  }
  if (!EstimatePrecision(&problem, intrinsics.data(), &result))
    return Error{
        "camera calibration: the views do not determine every free parameter (the "
        "normal matrix is singular): add views at other angles, or fix k3, p1 p2"};
  return result;
}

}  // namespace ts
