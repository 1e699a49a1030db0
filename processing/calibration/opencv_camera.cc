#include "processing/calibration/opencv_camera.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace ts {
namespace {

constexpr int kN = CameraIntrinsics::kNumParameters;
// fx fy cx cy skew k1 k2 p1 p2 k3 k4 k5 k6
constexpr int kOpenCvParameters = 13;

template <typename T>
void OpenCvPixel(const T* q, const T& x, const T& y, T* u, T* v) {
  const T r2 = x * x + y * y;
  const T radial = (T(1) + r2 * (q[5] + r2 * (q[6] + r2 * q[9]))) /
                   (T(1) + r2 * (q[10] + r2 * (q[11] + r2 * q[12])));
  const T xd = x * radial + T(2) * q[7] * x * y + q[8] * (r2 + T(2) * x * x);
  const T yd = y * radial + q[7] * (r2 + T(2) * y * y) + T(2) * q[8] * x * y;
  *u = q[0] * xd + q[4] * yd + q[2];
  *v = q[1] * yd + q[3];
}

std::array<double, kOpenCvParameters> Parameters(const OpenCvCamera& c) {
  std::array<double, kOpenCvParameters> q{};
  const cv::Mat& k = c.camera_matrix;
  q[0] = k.at<double>(0, 0), q[1] = k.at<double>(1, 1);
  q[2] = k.at<double>(0, 2), q[3] = k.at<double>(1, 2), q[4] = k.at<double>(0, 1);
  const int order[] = {5, 6, 7, 8, 9, 10, 11, 12};  // k1 k2 p1 p2 k3 k4 k5 k6
  for (int i = 0; i < static_cast<int>(c.dist_coeffs.total()) && i < 8; ++i)
    q[order[i]] = c.dist_coeffs.at<double>(i);
  return q;
}

OpenCvCamera FromParameters(const std::array<double, kOpenCvParameters>& q, int width, int height,
                            bool rational) {
  OpenCvCamera c;
  c.width_px = width;
  c.height_px = height;
  c.camera_matrix = (cv::Mat_<double>(3, 3) << q[0], q[4], q[2], 0, q[1], q[3], 0, 0, 1);
  if (rational)
    c.dist_coeffs = (cv::Mat_<double>(1, 8) << q[5], q[6], q[7], q[8], q[9], q[10], q[11], q[12]);
  else
    c.dist_coeffs = (cv::Mat_<double>(1, 5) << q[5], q[6], q[7], q[8], q[9]);
  return c;
}

// The frame's grid, every 1/40 of it and its border, in measured pixels.
std::vector<Eigen::Vector2d> FrameGrid(int width, int height) {
  std::vector<Eigen::Vector2d> grid;
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i)
      grid.emplace_back(-0.5 + width * i / 40.0, -0.5 + height * j / 40.0);
  return grid;
}

// OpenCV's model must send the ideal ray of each measured pixel back to that pixel.
struct OpenCvFit {
  Eigen::Vector2d ideal;  // normalised x/z, y/z
  Eigen::Vector2d pixel;
  template <typename T>
  bool operator()(const T* q, T* residual) const {
    T u, v;
    OpenCvPixel(q, T(ideal.x()), T(ideal.y()), &u, &v);
    residual[0] = u - T(pixel.x());
    residual[1] = v - T(pixel.y());
    return true;
  }
};

// The project's model must correct each measured pixel to its ideal ray (OpenCV's): explicit
// in the correction form, so finite wherever the fit wanders.
struct ProjectModelFit {
  Eigen::Vector2d ideal;
  Eigen::Vector2d pixel;
  template <typename T>
  bool operator()(const T* intrinsics, T* residual) const {
    const T rx = T(pixel.x()) - intrinsics[1], ry = T(pixel.y()) - intrinsics[2];
    T dx, dy;
    DistortionCorrection(intrinsics, rx, ry, &dx, &dy);
    residual[0] = rx + dx - intrinsics[0] * ideal.x();
    residual[1] = ry + dy - intrinsics[0] * ideal.y();
    return true;
  }
};

void Solve(ceres::Problem* problem) {
  FLAGS_minloglevel = google::GLOG_FATAL;  // a failed step is judged by the difference it leaves
  ceres::Solver::Options options;
  options.logging_type = ceres::SILENT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 500;
  options.function_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
}

// OpenCV's ideal normalised coordinates of a measured pixel, by Newton on its forward model.
bool UndistortOpenCv(const std::array<double, kOpenCvParameters>& q, const Eigen::Vector2d& pixel,
                     Eigen::Vector2d* ideal) {
  Eigen::Vector2d x((pixel.x() - q[2]) / q[0], (pixel.y() - q[3]) / q[1]);
  for (int it = 0; it < 50; ++it) {
    using Jet = ceres::Jet<double, 2>;
    Jet u, v;
    std::array<Jet, kOpenCvParameters> qj;
    for (int i = 0; i < kOpenCvParameters; ++i) qj[i] = Jet(q[i]);
    OpenCvPixel(qj.data(), Jet(x.x(), 0), Jet(x.y(), 1), &u, &v);
    Eigen::Matrix2d j;
    j << u.v[0], u.v[1], v.v[0], v.v[1];
    const Eigen::Vector2d step = j.lu().solve(Eigen::Vector2d(u.a, v.a) - pixel);
    if (!step.allFinite()) return false;
    x -= step;
    if (step.norm() < 1e-15) break;
  }
  *ideal = x;
  return x.allFinite();
}

// The project's correction is linear in its distortion and affinity terms once the principal
// distance and point are held (OpenCV's fy, cx, cy): i - r = d(r), solved in the least-squares
// sense over the grid, the start of the fit (ProjectModelFit).
std::array<double, kN> LinearStart(const std::array<double, kOpenCvParameters>& q,
                                   const std::vector<ProjectModelFit>& fits) {
  std::array<double, kN> p{q[1], q[2], q[3]};
  Eigen::MatrixXd a(2 * fits.size(), kN - 3);
  Eigen::VectorXd b(2 * fits.size());
  for (size_t k = 0; k < fits.size(); ++k) {
    const Eigen::Vector2d r = fits[k].pixel - Eigen::Vector2d(q[2], q[3]);
    const Eigen::Vector2d i = q[1] * fits[k].ideal;
    for (int j = 3; j < kN; ++j) {  // the column of term j: d(r) with only that term at 1
      std::array<double, kN> unit{q[1]};
      unit[j] = 1.0;
      double dx, dy;
      DistortionCorrection(unit.data(), r.x(), r.y(), &dx, &dy);
      a(2 * k, j - 3) = dx;
      a(2 * k + 1, j - 3) = dy;
    }
    b.segment<2>(2 * k) = i - r;
  }
  const Eigen::VectorXd terms = a.colPivHouseholderQr().solve(b);
  for (int j = 3; j < kN; ++j) p[j] = terms[j - 3];
  return p;
}

// OpenCV's distortion is linear in k1-k6, p1 p2 once the pinhole terms are held, if the
// rational model's denominator is carried to the other side (x_d D = x N + t, with t D taken as
// t): solved in the least-squares sense over the grid, the start of the fit in pixels.
void LinearOpenCvStart(const std::vector<OpenCvFit>& fits, bool rational,
                       std::array<double, kOpenCvParameters>* q) {
  const std::vector<int> terms =
      rational ? std::vector<int>{5, 6, 9, 10, 11, 12, 7, 8} : std::vector<int>{5, 6, 9, 7, 8};
  Eigen::MatrixXd a(2 * fits.size(), terms.size());
  Eigen::VectorXd b(2 * fits.size());
  for (size_t k = 0; k < fits.size(); ++k) {
    const Eigen::Vector2d& x = fits[k].ideal;
    const double yd = (fits[k].pixel.y() - (*q)[3]) / (*q)[1];
    const double xd = (fits[k].pixel.x() - (*q)[2] - (*q)[4] * yd) / (*q)[0];
    const double r2 = x.squaredNorm();
    const Eigen::Vector2d d(xd, yd);
    for (size_t t = 0; t < terms.size(); ++t)
      for (int axis = 0; axis < 2; ++axis) {
        double value = 0.0;
        switch (terms[t]) {
          case 5:
            value = x[axis] * r2;
            break;
          case 6:
            value = x[axis] * r2 * r2;
            break;
          case 9:
            value = x[axis] * r2 * r2 * r2;
            break;
          case 10:
            value = -d[axis] * r2;
            break;
          case 11:
            value = -d[axis] * r2 * r2;
            break;
          case 12:
            value = -d[axis] * r2 * r2 * r2;
            break;
          case 7:
            value = axis == 0 ? 2 * x.x() * x.y() : r2 + 2 * x.y() * x.y();
            break;
          case 8:
            value = axis == 0 ? r2 + 2 * x.x() * x.x() : 2 * x.x() * x.y();
            break;
        }
        a(2 * k + axis, t) = value;
      }
    b.segment<2>(2 * k) = d - x;
  }
  const Eigen::VectorXd solution = a.colPivHouseholderQr().solve(b);
  for (size_t t = 0; t < terms.size(); ++t) (*q)[terms[t]] = solution[t];
}

// OpenCV's 5 or 8 coefficients fitted to the grid; the difference they leave in conversion.
OpenCvCamera FitOpenCv(const CameraIntrinsics& camera, const std::vector<OpenCvFit>& fits,
                       bool rational, ModelConversion* conversion) {
  std::array<double, kOpenCvParameters> q{};
  q[0] = camera.principal_distance_px / (1.0 + camera.scale_x);
  q[1] = camera.principal_distance_px;
  q[2] = camera.principal_point_x_px, q[3] = camera.principal_point_y_px;
  LinearOpenCvStart(fits, rational, &q);
  ceres::Problem problem;
  for (const OpenCvFit& f : fits)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<OpenCvFit, 2, kOpenCvParameters>(new OpenCvFit(f)), nullptr,
        q.data());
  // The skew stays zero: OpenCV's projectPoints does not apply it.
  problem.SetManifold(q.data(), new ceres::SubsetManifold(
                                    kOpenCvParameters, rational ? std::vector<int>{4}
                                                                : std::vector<int>{4, 10, 11, 12}));
  Solve(&problem);
  conversion->max_difference_px = 0.0;
  for (const OpenCvFit& f : fits) {
    Eigen::Vector2d pixel;
    OpenCvPixel(q.data(), f.ideal.x(), f.ideal.y(), &pixel.x(), &pixel.y());
    conversion->max_difference_px =
        std::max(conversion->max_difference_px, (pixel - f.pixel).norm());
  }
  return FromParameters(q, camera.width_px, camera.height_px, rational);
}

}  // namespace

Eigen::Vector2d ProjectOpenCv(const OpenCvCamera& camera, const Eigen::Vector3d& point) {
  const auto q = Parameters(camera);
  double u, v;
  OpenCvPixel(q.data(), point.x() / point.z(), point.y() / point.z(), &u, &v);
  return {u, v};
}

Result<OpenCvCamera> ToOpenCv(const CameraIntrinsics& camera, ModelConversion* conversion) {
  std::string why;
  if (!camera.Check(&why)) return Error{why};
  // A symmetric shear is a skew and a turn of the camera about its axis, and OpenCV's
  // projectPoints ignores a skew: what the fit cannot follow stays in max_difference_px.
  const CameraModel model(camera);
  std::vector<OpenCvFit> fits;
  for (const Eigen::Vector2d& pixel : FrameGrid(camera.width_px, camera.height_px)) {
    const Eigen::Vector3d ray = model.RayFromPixel(pixel);
    fits.push_back({ray.head<2>() / ray.z(), pixel});
  }
  const OpenCvCamera five = FitOpenCv(camera, fits, false, conversion);
  if (conversion->max_difference_px <= conversion->tolerance_px) return five;
  return FitOpenCv(camera, fits, true, conversion);
}

Result<CameraIntrinsics> FromOpenCv(const OpenCvCamera& camera, ModelConversion* conversion) {
  if (camera.camera_matrix.rows != 3 || camera.camera_matrix.cols != 3 ||
      camera.camera_matrix.type() != CV_64F)
    return Error{"cameraMatrix: must be a 3 x 3 matrix of doubles"};
  const int n = static_cast<int>(camera.dist_coeffs.total());
  if (camera.dist_coeffs.type() != CV_64F || (n != 0 && n != 4 && n != 5 && n != 8))
    return Error{"distCoeffs: must hold 4, 5 or 8 doubles (k1 k2 p1 p2 [k3 [k4 k5 k6]])"};
  const auto q = Parameters(camera);
  for (double value : q)
    if (!std::isfinite(value)) return Error{"cameraMatrix, distCoeffs: must be finite"};
  if (!(q[0] > 0.0) || !(q[1] > 0.0)) return Error{"cameraMatrix: fx and fy must be positive"};
  // OpenCV's calibrations never estimate one; the project's shear is symmetric (seed 000).
  if (q[4] != 0.0) return Error{"cameraMatrix: a skew (row 0, column 1) is not supported"};
  std::vector<ProjectModelFit> fits;
  for (const Eigen::Vector2d& pixel : FrameGrid(camera.width_px, camera.height_px)) {
    Eigen::Vector2d ideal;
    if (!UndistortOpenCv(q, pixel, &ideal))
      return Error{"distCoeffs: the model cannot be inverted over the frame"};
    fits.push_back({ideal, pixel});
  }
  // With k3 free the fit may bend the correction back just beyond the frame, where projection
  // then fails; the fit with k3 held at zero is tried too and the closer one kept.
  CameraIntrinsics best;
  conversion->max_difference_px = std::numeric_limits<double>::infinity();
  for (bool hold_k3 : {false, true}) {
    std::array<double, kN> p = LinearStart(q, fits);
    if (hold_k3) p[5] = 0.0;
    ceres::Problem problem;
    for (const ProjectModelFit& f : fits)
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ProjectModelFit, 2, kN>(new ProjectModelFit(f)), nullptr,
          p.data());
    if (hold_k3) problem.SetManifold(p.data(), new ceres::SubsetManifold(kN, {5}));
    Solve(&problem);
    const CameraIntrinsics c =
        CameraIntrinsics::FromParameters(p, camera.width_px, camera.height_px, 0.0);
    if (!c.Check(nullptr)) continue;
    const CameraModel model(c);
    double worst = 0.0;
    for (const ProjectModelFit& f : fits) {
      Eigen::Vector2d pixel;
      worst = std::max(worst, model.Project(f.ideal.homogeneous(), &pixel)
                                  ? (pixel - f.pixel).norm()
                                  : std::numeric_limits<double>::infinity());
    }
    if (worst < conversion->max_difference_px) conversion->max_difference_px = worst, best = c;
  }
  if (!(conversion->max_difference_px <= conversion->refuse_px))
    return Error{"distCoeffs: the project's lens model follows this one only to " +
                 std::to_string(conversion->max_difference_px) +
                 " px over the frame (refused above " + std::to_string(conversion->refuse_px) +
                 " px)"};
  return best;
}

}  // namespace ts
