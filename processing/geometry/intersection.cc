#include "processing/geometry/intersection.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "processing/geometry/rotation.h"

namespace ts {

bool IntersectionOptions::Check(std::string* why) const {
  std::string err;
  if (max_iterations < 1)
    err = "max_iterations must be at least 1";
  else if (!(step_tolerance_m > 0.0))
    err = "step_tolerance_m must be positive";
  else if (!(min_ray_angle_deg >= 0.0 && min_ray_angle_deg < 90.0))
    err = "min_ray_angle_deg must be in [0, 90)";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

// Point minimising the sum of squared distances to the rays.
bool LinearStart(const std::vector<RayObservation>& rays, double min_angle_rad,
                 Eigen::Vector3d* point) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> directions;
  for (const RayObservation& ray : rays) {
    const Eigen::Vector3d d = ray.world_from_camera.linear() * ray.camera->RayFromPixel(ray.pixel);
    const Eigen::Matrix3d p = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += p;
    b += p * ray.world_from_camera.translation();
    directions.push_back(d);
  }
  double max_angle = 0.0;
  for (size_t i = 0; i < directions.size(); ++i)
    for (size_t j = i + 1; j < directions.size(); ++j)
      max_angle =
          std::max(max_angle, std::acos(std::clamp(directions[i].dot(directions[j]), -1.0, 1.0)));
  if (max_angle < std::max(min_angle_rad, 1e-12)) return false;
  *point = a.ldlt().solve(b);
  return point->allFinite();
}

struct NormalEquations {
  Eigen::Matrix3d n = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();  // J^T W r
  double weighted_sum = 0.0;
  double sum_squares_px = 0.0;
  bool ok = true;
};

NormalEquations Accumulate(const std::vector<RayObservation>& rays, const Eigen::Vector3d& x) {
  NormalEquations ne;
  for (const RayObservation& ray : rays) {
    const Eigen::Isometry3d camera_from_world = ray.world_from_camera.inverse();
    Eigen::Vector2d predicted;
    CameraModel::Jacobian2x3 j_point;
    if (!ray.camera->Project(camera_from_world * x, &predicted, &j_point)) {
      ne.ok = false;
      return ne;
    }
    const Eigen::Matrix<double, 2, 3> j = j_point * camera_from_world.linear();
    const Eigen::Vector2d r = predicted - ray.pixel;
    const double w = 1.0 / (ray.sigma_px * ray.sigma_px);
    ne.n += w * j.transpose() * j;
    ne.g += w * j.transpose() * r;
    ne.weighted_sum += w * r.squaredNorm();
    ne.sum_squares_px += r.squaredNorm();
  }
  return ne;
}

}  // namespace

IntersectionResult IntersectRays(const std::vector<RayObservation>& rays,
                                 const IntersectionOptions& options) {
  IntersectionResult result;
  if (!options.Check(&result.why)) return result;
  if (rays.size() < 2) {
    result.why = "need at least two rays";
    return result;
  }
  for (const RayObservation& ray : rays) {
    if (!ray.camera || !(ray.sigma_px > 0.0) || !ray.pixel.allFinite()) {
      result.why = "every ray needs a camera, a finite pixel and a positive sigma";
      return result;
    }
  }
  Eigen::Vector3d x;
  if (!LinearStart(rays, RadFromDeg(options.min_ray_angle_deg), &x)) {
    result.why = "rays are (nearly) parallel";
    return result;
  }
  NormalEquations ne;
  for (result.iterations = 1; result.iterations <= options.max_iterations; ++result.iterations) {
    ne = Accumulate(rays, x);
    if (!ne.ok) {
      result.why = "point falls behind a camera";
      return result;
    }
    const Eigen::Vector3d step = -ne.n.ldlt().solve(ne.g);
    if (!step.allFinite()) {
      result.why = "singular normal equations";
      return result;
    }
    x += step;
    if (step.norm() < options.step_tolerance_m) break;
  }
  ne = Accumulate(rays, x);
  if (!ne.ok) {
    result.why = "point falls behind a camera";
    return result;
  }
  result.point_world = x;
  result.covariance_m2 = ne.n.inverse();
  result.rms_residual_px = std::sqrt(ne.sum_squares_px / (2.0 * rays.size()));
  result.usable = result.covariance_m2.allFinite();
  if (!result.usable) result.why = "singular covariance";
  return result;
}

}  // namespace ts
