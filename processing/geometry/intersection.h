#pragma once
// Space intersection of two or more image rays (forward intersection).
//
// A linear start (the point closest to all rays in the least-squares sense) is refined by
// Gauss-Newton on the collinearity equations of camera_model.h, each image coordinate
// weighted by 1/sigma^2. The 3x3 covariance of the point is the inverse normal matrix with
// the a-priori image sigmas (sigma0 = 1): with two rays the redundancy is one, far too little
// to rescale by the a-posteriori variance factor.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "processing/geometry/camera_model.h"

namespace ts {

struct RayObservation {
  const CameraModel* camera = nullptr;  // borrowed; must outlive the call
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // measured pixel
  double sigma_px = 1.0 / 3.0;                      // standard deviation of each coordinate
};

struct IntersectionOptions {
  int max_iterations = 10;          // Gauss-Newton iterations
  double step_tolerance_m = 1e-9;   // stop when the update is shorter than this
  double min_ray_angle_deg = 0.01;  // rays more parallel than this do not intersect
  bool Check(std::string* why) const;
};

struct IntersectionResult {
  bool usable = false;  // false: see why
  std::string why;      // reason when not usable
  Eigen::Vector3d point_world = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance_m2 = Eigen::Matrix3d::Zero();
  double rms_residual_px = 0.0;  // RMS of all image residuals at the solution
  int iterations = 0;
};

IntersectionResult IntersectRays(const std::vector<RayObservation>& rays,
                                 const IntersectionOptions& options = {});

}  // namespace ts
