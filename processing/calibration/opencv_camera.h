#pragma once
// OpenCV's camera model beside the project's one (camera_model.h), and the conversion between
// them. OpenCV distorts ideal normalised coordinates into measured ones (x_d = x (1 + k1 r^2 +
// k2 r^4 + k3 r^6) / (1 + k4 r^2 + k5 r^4 + k6 r^6) + tangential; u = fx x_d + skew y_d + cx);
// the project corrects measured coordinates into ideal ones (seed 000). One is not the other's
// coefficients with the signs turned: each conversion fits the target model to the source over a
// dense grid of the frame (Ceres) and says how far apart the two still project
// (max_difference_px). Export uses OpenCV's rational model (8 coefficients) only when its 5
// leave more than the tolerance. Radial terms convert to a few micro-pixels; decentring terms
// under strong radial distortion do not (the inverse of one has radial-times-decentring terms
// the other lacks: about p * k1 * c at the frame's corners), and the difference is reported.
#include <opencv2/core.hpp>

#include "core/result.h"
#include "processing/geometry/camera_model.h"

namespace ts {

struct OpenCvCamera {
  int width_px = 0;
  int height_px = 0;
  cv::Mat camera_matrix;  // 3 x 3, CV_64F
  cv::Mat dist_coeffs;    // 1 x 4, 5, 8 (k1 k2 p1 p2 [k3 [k4 k5 k6]]), CV_64F
};

struct ModelConversion {
  double max_difference_px = 0.0;  // over the frame's grid, after the fit
  double tolerance_px = 0.01;      // the callers warn above it
  double refuse_px = 1.0;          // no longer the same camera: an import is refused
};

// Pixel of a point in the camera frame in OpenCV's model (as cv::projectPoints).
Eigen::Vector2d ProjectOpenCv(const OpenCvCamera& camera, const Eigen::Vector3d& point);

Result<OpenCvCamera> ToOpenCv(const CameraIntrinsics& camera, ModelConversion* conversion);
// Errors when the project's model cannot follow OpenCV's within refuse_px over the frame (for
// example a rational model with strong k4-k6).
Result<CameraIntrinsics> FromOpenCv(const OpenCvCamera& camera, ModelConversion* conversion);

}  // namespace ts
