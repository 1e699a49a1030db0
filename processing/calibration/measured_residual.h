#pragma once
// The residual every calibration adjusts, in measured pixels, templated for Ceres's automatic
// derivatives; shared by the target adjustment and the conversion of OpenCV's lens model.
#include <ceres/jet.h>

#include <Eigen/Core>

#include "processing/geometry/camera_model.h"

namespace ts {

// A point in a camera frame to its residual in measured pixels: the ideal reduced image
// coordinates i = c (X/Z, Y/Z), then the measured reduced r with r + d(r) = i (camera_model.h)
// by fixed-point iteration r <- i - d(r). It contracts by the derivative of d, about 0.5 at the
// corners of a strongly distorting lens: 40 steps leave far less than a micro-pixel.
template <typename T>
bool MeasuredResidual(const T* intrinsics, const T* p, const Eigen::Vector2d& pixel, T* residual) {
  if (!(p[2] > T(0))) return false;
  const T ix = intrinsics[0] * p[0] / p[2], iy = intrinsics[0] * p[1] / p[2];
  T rx = ix, ry = iy;
  for (int k = 0; k < 40; ++k) {
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

}  // namespace ts
