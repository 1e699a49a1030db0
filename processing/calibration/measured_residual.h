#pragma once
// The residual every calibration adjusts, in measured pixels, templated for Ceres's automatic
// derivatives; shared by the target adjustment and the conversion of OpenCV's lens model.
#include <ceres/jet.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <cmath>

#include "processing/geometry/camera_model.h"

namespace ts {

inline double ValueOf(double x) { return x; }
template <typename T, int N>
double ValueOf(const ceres::Jet<T, N>& x) {
  return x.a;
}
// Value and derivatives finite (ceres::isfinite looks at the value only).
inline bool AllFinite(double x) { return std::isfinite(x); }
template <typename T, int N>
bool AllFinite(const ceres::Jet<T, N>& x) {
  return std::isfinite(x.a) && x.v.allFinite();
}

// A point in a camera frame to its residual in measured pixels: the ideal reduced image
// coordinates i = c (X/Z, Y/Z), then the measured reduced r with r + d(r) = i (camera_model.h).
// r by fixed-point iteration r <- i - d(r) on plain numbers: it contracts by the derivative of
// d, about 0.5 at the corners of a strongly distorting lens, so 40 steps leave far less than a
// micro-pixel. Then one Newton step in T: its value is r, and its derivatives are those of the
// implicit function theorem, dr = -(I + dd/dr)^-1 dF, as exact as iterating in T and 40 times
// cheaper for Ceres's jets.
template <typename T>
bool MeasuredResidual(const T* intrinsics, const T* p, const Eigen::Vector2d& pixel, T* residual) {
  if (!(p[2] > T(0))) return false;
  const T ix = intrinsics[0] * p[0] / p[2], iy = intrinsics[0] * p[1] / p[2];
  constexpr int kN = CameraIntrinsics::kNumParameters;
  using Dual = ceres::Jet<double, 2>;  // derivatives in rx, ry
  std::array<double, kN> values;
  std::array<Dual, kN> duals;
  for (int j = 0; j < kN; ++j) duals[j] = Dual(values[j] = ValueOf(intrinsics[j]));
  const double ix0 = ValueOf(ix), iy0 = ValueOf(iy);
  double rx0 = ix0, ry0 = iy0;
  for (int k = 0; k < 40; ++k) {
    double dx, dy;
    DistortionCorrection(values.data(), rx0, ry0, &dx, &dy);
    rx0 = ix0 - dx;
    ry0 = iy0 - dy;
  }
  Dual dx, dy;
  DistortionCorrection(duals.data(), Dual(rx0, 0), Dual(ry0, 1), &dx, &dy);
  // Beyond the lens's range the iteration does not settle, or settles where the correction
  // folds over (r + d(r) no longer one to one): a step there is refused.
  Eigen::Matrix2d jacobian;  // of r + d(r)
  jacobian << 1.0 + dx.v[0], dx.v[1], dy.v[0], 1.0 + dy.v[1];
  if (!(std::hypot(rx0 + dx.a - ix0, ry0 + dy.a - iy0) < 1e-6) || !(jacobian.determinant() > 0.0))
    return false;
  const Eigen::Matrix2d inverse = jacobian.inverse();
  T fx, fy;  // F = r + d(r) - i at r0, with its derivatives in the parameters
  DistortionCorrection(intrinsics, T(rx0), T(ry0), &fx, &fy);
  fx += T(rx0) - ix;
  fy += T(ry0) - iy;
  const T rx = T(rx0) - (inverse(0, 0) * fx + inverse(0, 1) * fy);
  const T ry = T(ry0) - (inverse(1, 0) * fx + inverse(1, 1) * fy);
  residual[0] = intrinsics[1] + rx - T(pixel.x());
  residual[1] = intrinsics[2] + ry - T(pixel.y());
  return AllFinite(residual[0]) && AllFinite(residual[1]);
}

}  // namespace ts
