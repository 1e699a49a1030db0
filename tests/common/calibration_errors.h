#pragma once
// A calibration against the simulated rig's truth: errors with their sigmas, collected over
// seeds (are the sigmas honest?), and the distortion's difference over the frame.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "processing/calibration/camera_calibration.h"
#include "processing/geometry/rotation.h"

namespace ts {

struct CalibrationErrors {
  std::vector<double> values, sigmas;
  void Add(double error, double sigma) {
    values.push_back(error);
    sigmas.push_back(sigma);
  }
  double MaxAbs() const {
    double m = 0.0;
    for (double v : values) m = std::max(m, std::abs(v));
    return m;
  }
  // Near 1 when the sigmas describe the errors.
  double NormalisedRms() const {
    double s = 0.0;
    for (size_t k = 0; k < values.size(); ++k) s += std::pow(values[k] / sigmas[k], 2);
    return std::sqrt(s / values.size());
  }
};

// The largest difference of the distortion corrections d(r) over the frame, at the same r.
inline double DistortionDifferencePx(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  const auto pa = a.ToParameters(), pb = b.ToParameters();
  double worst = 0.0;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const double rx = a.width_px * i / 20.0 - a.principal_point_x_px;
      const double ry = a.height_px * j / 20.0 - a.principal_point_y_px;
      double ax, ay, bx, by;
      DistortionCorrection(pa.data(), rx, ry, &ax, &ay);
      DistortionCorrection(pb.data(), rx, ry, &bx, &by);
      worst = std::max(worst, std::hypot(ax - bx, ay - by));
    }
  return worst;
}

// omega phi kappa of left_from_right, in degrees, as StereoCalibration::angles_deg.
inline Eigen::Vector3d RelativeAnglesDeg(const StereoRig& rig) {
  const Opk opk = OpkFromRotation(rig.left_from_right);
  return {DegFromRad(opk.omega_rad), DegFromRad(opk.phi_rad), DegFromRad(opk.kappa_rad)};
}

// The stereo calibration's errors added: principal distance (relative), principal point,
// baseline, angles.
struct StereoErrors {
  CalibrationErrors c_rel, pp, baseline, angles;
  double distortion_px = 0.0;  // largest over the cameras
  void Add(const StereoCalibration& s, const StereoRig& truth) {
    for (const auto& [est, tru] :
         {std::pair{&s.left, &truth.left}, std::pair{&s.right, &truth.right}}) {
      const CameraIntrinsics& e = est->intrinsics;
      c_rel.Add(e.principal_distance_px / tru->principal_distance_px - 1.0,
                est->sigma[0] / tru->principal_distance_px);
      pp.Add(e.principal_point_x_px - tru->principal_point_x_px, est->sigma[1]);
      pp.Add(e.principal_point_y_px - tru->principal_point_y_px, est->sigma[2]);
      distortion_px = std::max(distortion_px, DistortionDifferencePx(e, *tru));
    }
    baseline.Add(s.baseline - truth.baseline_m, s.baseline_sigma);
    const Eigen::Vector3d angles_true = RelativeAnglesDeg(truth);
    for (int j = 0; j < 3; ++j) angles.Add(s.angles_deg[j] - angles_true[j], s.angles_sigma_deg[j]);
  }
};

}  // namespace ts
