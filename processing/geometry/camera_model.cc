#include "processing/geometry/camera_model.h"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

namespace ts {
namespace {
constexpr int kMaxNewtonIterations = 30;
constexpr double kNewtonToleranceSquaredPx = 1e-20;

bool Finite(double v) { return std::isfinite(v); }
}  // namespace

// What a real camera can be: a sensor up to 65535 px a side, a field of view across its
// width between 1 and 170 degrees, the principal point on the sensor, and a distortion that
// moves no point of the image by more than half its distance from the principal point (a
// k1 of 1e6 took the whole image a thousand widths away, and a survey came out with 7 points).
constexpr int kMaxSensorSidePx = 65535;
constexpr double kMinFieldOfViewDeg = 1.0, kMaxFieldOfViewDeg = 170.0;
constexpr double kMaxDistortionShare = 0.5;

bool CameraIntrinsics::Check(std::string* why) const {
  std::ostringstream err;
  const double w = width_px, h = height_px;
  auto half_tan = [](double deg) { return std::tan(deg * M_PI / 360.0); };
  if (width_px <= 0 || height_px <= 0 || width_px > kMaxSensorSidePx ||
      height_px > kMaxSensorSidePx)
    err << "image size must be 1 to " << kMaxSensorSidePx << " px a side, got " << width_px << " x "
        << height_px;
  else if (!Finite(principal_distance_px) || principal_distance_px <= 0.0)
    err << "principal_distance_px must be a finite positive number";
  else if (principal_distance_px < 0.5 * w / half_tan(kMaxFieldOfViewDeg) ||
           principal_distance_px > 0.5 * w / half_tan(kMinFieldOfViewDeg))
    err << "principal_distance_px " << principal_distance_px << " gives a field of view outside "
        << kMinFieldOfViewDeg << "-" << kMaxFieldOfViewDeg << " deg across " << width_px << " px";
  else if (!Finite(pixel_size_um) || pixel_size_um < 0.0 || pixel_size_um > 100.0)
    err << "pixel_size_um must be 0 (unknown) to 100";
  else {
    for (int i = 1; i < kNumParameters; ++i) {
      if (!Finite(ToParameters()[i])) {
        err << kParameterNames[i] << " must be finite";
        break;
      }
    }
  }
  if (err.str().empty() && (principal_point_x_px < -0.5 || principal_point_x_px > w - 0.5 ||
                            principal_point_y_px < -0.5 || principal_point_y_px > h - 0.5))
    err << "principal point (" << principal_point_x_px << ", " << principal_point_y_px
        << ") px is off the " << width_px << " x " << height_px << " image";
  if (err.str().empty()) {
    const std::array<double, kNumParameters> p = ToParameters();
    const double xp = principal_point_x_px, yp = principal_point_y_px;
    for (const double cx : {-0.5 - xp, w - 0.5 - xp})
      for (const double cy : {-0.5 - yp, h - 0.5 - yp}) {
        double dx = 0.0, dy = 0.0;
        DistortionCorrection(p.data(), cx, cy, &dx, &dy);
        if (err.str().empty() &&
            !(std::hypot(dx, dy) <= kMaxDistortionShare * std::hypot(cx, cy))) {
          const double moved = std::hypot(dx, dy);
          err << "distortion and affinity move the image's corner by ";
          if (std::isfinite(moved))
            err << moved << " px";
          else
            err << "more than a double holds";
          err << ", more than half its " << std::hypot(cx, cy)
              << " px from the principal point: no real lens";
        }
      }
  }
  if (err.str().empty()) return true;
  if (why) *why = err.str();
  return false;
}

std::array<double, CameraIntrinsics::kNumParameters> CameraIntrinsics::ToParameters() const {
  return {principal_distance_px,
          principal_point_x_px,
          principal_point_y_px,
          k1,
          k2,
          k3,
          p1,
          p2,
          scale_x,
          shear};
}

CameraIntrinsics CameraIntrinsics::FromParameters(const std::array<double, kNumParameters>& p,
                                                  int width_px, int height_px,
                                                  double pixel_size_um) {
  CameraIntrinsics c;
  c.width_px = width_px;
  c.height_px = height_px;
  c.pixel_size_um = pixel_size_um;
  c.principal_distance_px = p[0];
  c.principal_point_x_px = p[1];
  c.principal_point_y_px = p[2];
  c.k1 = p[3];
  c.k2 = p[4];
  c.k3 = p[5];
  c.p1 = p[6];
  c.p2 = p[7];
  c.scale_x = p[8];
  c.shear = p[9];
  return c;
}

CameraModel::CameraModel(const CameraIntrinsics& intrinsics)
    : intrinsics_(intrinsics),
      params_(intrinsics.ToParameters()),
      principal_point_(intrinsics.principal_point_x_px, intrinsics.principal_point_y_px) {}

Eigen::Vector2d CameraModel::IdealReduced(const Eigen::Vector2d& r,
                                          Eigen::Matrix2d* jacobian) const {
  Eigen::Vector2d d;
  DistortionCorrection(params_.data(), r.x(), r.y(), &d.x(), &d.y());
  if (jacobian) {
    // d(c f(r/c))/dr = J_f(n); closed form of the partial derivatives of seed 000 eqs. 4-5.
    const double c = params_[0], k1 = params_[3], k2 = params_[4], k3 = params_[5];
    const double p1 = params_[6], p2 = params_[7], sx = params_[8], a = params_[9];
    const double nx = r.x() / c, ny = r.y() / c, r2 = nx * nx + ny * ny;
    const double radial = r2 * (k1 + r2 * (k2 + r2 * k3));
    const double radial_d = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);  // d radial / d r2
    const double off = a + 2.0 * nx * ny * radial_d + 2.0 * p1 * ny + 2.0 * p2 * nx;
    *jacobian << 1.0 + sx + radial + 2.0 * nx * nx * radial_d + 6.0 * p1 * nx + 2.0 * p2 * ny, off,
        off, 1.0 + radial + 2.0 * ny * ny * radial_d + 2.0 * p1 * nx + 6.0 * p2 * ny;
  }
  return r + d;
}

bool CameraModel::SolveReduced(const Eigen::Vector2d& ideal, Eigen::Vector2d* r,
                               Eigen::Matrix2d* jacobian) const {
  Eigen::Vector2d x = ideal;
  Eigen::Matrix2d j;
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    const Eigen::Vector2d f = IdealReduced(x, &j) - ideal;
    if (!f.allFinite() || std::abs(j.determinant()) < 1e-6) return false;
    const Eigen::Vector2d step = j.inverse() * f;
    x -= step;
    if (step.squaredNorm() < kNewtonToleranceSquaredPx) {
      IdealReduced(x, &j);
      *r = x;
      if (jacobian) *jacobian = j;
      return true;
    }
  }
  return false;
}

bool CameraModel::Project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel,
                          Jacobian2x3* d_pixel_d_point,
                          JacobianIntrinsics* d_pixel_d_intrinsics) const {
  if (!(p.z() > 0.0) || !p.allFinite()) return false;
  const double c = params_[0];
  const Eigen::Vector2d normal(p.x() / p.z(), p.y() / p.z());
  Eigen::Vector2d r;
  Eigen::Matrix2d j;  // d ideal / d r
  if (!SolveReduced(c * normal, &r, &j)) return false;
  *pixel = principal_point_ + r;
  if (!d_pixel_d_point && !d_pixel_d_intrinsics) return true;

  // Implicit differentiation of r + d(r; theta) = i(theta, P): dr = J^-1 (di - dd/dtheta).
  const Eigen::Matrix2d j_inv = j.inverse();
  if (d_pixel_d_point) {
    Jacobian2x3 di_dp;
    const double iz = 1.0 / p.z();
    di_dp << c * iz, 0.0, -c * p.x() * iz * iz, 0.0, c * iz, -c * p.y() * iz * iz;
    *d_pixel_d_point = j_inv * di_dp;
  }
  if (d_pixel_d_intrinsics) {
    const double nx = r.x() / c, ny = r.y() / c, r2 = nx * nx + ny * ny;
    Eigen::Vector2d f;  // d / c
    DistortionCorrection(params_.data(), r.x(), r.y(), &f.x(), &f.y());
    f /= c;
    // dd/dc = f(n) - J_f(n) n, with J_f = j - I.
    const Eigen::Vector2d n(nx, ny);
    Eigen::Matrix<double, 2, CameraIntrinsics::kNumParameters> dd;
    dd.setZero();
    dd.col(0) = f - (j - Eigen::Matrix2d::Identity()) * n;
    dd.col(3) = c * r2 * n;
    dd.col(4) = c * r2 * r2 * n;
    dd.col(5) = c * r2 * r2 * r2 * n;
    dd.col(6) << c * (r2 + 2.0 * nx * nx), c * 2.0 * nx * ny;
    dd.col(7) << c * 2.0 * nx * ny, c * (r2 + 2.0 * ny * ny);
    dd.col(8) << c * nx, 0.0;
    dd.col(9) << c * ny, c * nx;
    Eigen::Matrix<double, 2, CameraIntrinsics::kNumParameters> di;
    di.setZero();
    di.col(0) = normal;
    *d_pixel_d_intrinsics = j_inv * (di - dd);
    d_pixel_d_intrinsics->col(1) << 1.0, 0.0;  // the principal point shifts the pixel 1:1
    d_pixel_d_intrinsics->col(2) << 0.0, 1.0;
  }
  return true;
}

Eigen::Vector3d CameraModel::RayFromPixel(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d ideal = IdealReduced(pixel - principal_point_, nullptr);
  return Eigen::Vector3d(ideal.x(), ideal.y(), params_[0]).normalized();
}

Eigen::Vector2d CameraModel::Undistort(const Eigen::Vector2d& pixel,
                                       Eigen::Matrix2d* d_ideal_d_pixel) const {
  return principal_point_ + IdealReduced(pixel - principal_point_, d_ideal_d_pixel);
}

bool CameraModel::Distort(const Eigen::Vector2d& ideal_pixel, Eigen::Vector2d* pixel) const {
  Eigen::Vector2d r;
  if (!SolveReduced(ideal_pixel - principal_point_, &r, nullptr)) return false;
  *pixel = principal_point_ + r;
  return true;
}

bool CameraModel::InImage(const Eigen::Vector2d& pixel) const {
  return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() <= intrinsics_.width_px - 0.5 &&
         pixel.y() <= intrinsics_.height_px - 0.5;
}

}  // namespace ts
