#include "processing/geometry/inclinometer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "processing/geometry/rotation.h"

namespace ts {
namespace {

constexpr double kRad = M_PI / 180.0;

// The largest gap between neighbouring pans round the circle: readings whose pans all lie
// within a small arc (a gap near 360 deg) cannot turn the levelling against the index error.
double LargestPanGap(std::vector<double> pans) {
  for (double& p : pans) p = std::fmod(std::fmod(p, 360.0) + 360.0, 360.0);
  std::sort(pans.begin(), pans.end());
  double gap = 360.0 - (pans.back() - pans.front());
  for (size_t i = 1; i < pans.size(); ++i) gap = std::max(gap, pans[i] - pans[i - 1]);
  return gap;
}

}  // namespace

Eigen::Vector2d InclinometerReads(const StageKinematics& stage, double pan_deg,
                                  const Eigen::Vector2d& index_error_deg) {
  // The platform in L, as StageKinematics turns it: levelling, then the pan.
  const Eigen::Matrix3d l_from_platform = RotationX(stage.levelling_x_deg * kRad) *
                                          RotationY(stage.levelling_y_deg * kRad) *
                                          RotationZ(-(pan_deg - stage.pan_zero_deg) * kRad);
  // Gravity in the platform's frame; a platform levelled by (x, y) at pan 0 sees
  // (cos x sin y, -sin x, -cos x cos y).
  const Eigen::Vector3d g = l_from_platform.transpose() * Eigen::Vector3d(0, 0, -1);
  return Eigen::Vector2d(std::asin(std::clamp(-g.y(), -1.0, 1.0)), std::atan2(g.x(), -g.z())) /
             kRad +
         index_error_deg;
}

std::optional<LevellingFit> FitLevelling(const std::vector<InclinometerReading>& readings,
                                         const StageKinematics& stage, double reading_sigma_deg) {
  if (readings.size() < 3) return std::nullopt;
  std::vector<double> pans;
  for (const InclinometerReading& r : readings) pans.push_back(r.pan_deg);
  if (LargestPanGap(pans) > 300.0) return std::nullopt;
  // Unknowns: levelling x, y and index error x, y. Gauss-Newton on the exact model from zero
  // (small angles: nearly linear, a step or two).
  Eigen::Vector4d x = Eigen::Vector4d::Zero();
  const int n = static_cast<int>(readings.size());
  Eigen::MatrixXd a(2 * n, 4);
  Eigen::VectorXd residual(2 * n);
  auto model = [&](const Eigen::Vector4d& p, double pan) {
    StageKinematics s = stage;
    s.levelling_x_deg = p[0];
    s.levelling_y_deg = p[1];
    return InclinometerReads(s, pan, p.tail<2>());
  };
  for (int iteration = 0; iteration < 5; ++iteration) {
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d at = model(x, readings[i].pan_deg);
      residual.segment<2>(2 * i) = readings[i].tilt_deg - at;
      for (int j = 0; j < 4; ++j) {
        Eigen::Vector4d step = x;
        step[j] += 1e-4;
        a.block<2, 1>(2 * i, j) = (model(step, readings[i].pan_deg) - at) / 1e-4;
      }
    }
    const Eigen::Vector4d dx = (a.transpose() * a).ldlt().solve(a.transpose() * residual);
    x += dx;
    if (dx.norm() < 1e-9) break;
  }
  for (int i = 0; i < n; ++i)
    residual.segment<2>(2 * i) = readings[i].tilt_deg - model(x, readings[i].pan_deg);
  const int redundancy = 2 * n - 4;
  const double sigma0 =
      redundancy > 0 ? std::sqrt(residual.squaredNorm() / redundancy) : reading_sigma_deg;
  const Eigen::Matrix4d cofactor = (a.transpose() * a).inverse();
  const double sigma = std::max(sigma0, reading_sigma_deg);
  LevellingFit fit;
  fit.levelling_deg = x.head<2>();
  fit.index_error_deg = x.tail<2>();
  fit.levelling_sigma_deg = sigma * std::sqrt(std::max(cofactor(0, 0), cofactor(1, 1)));
  return fit;
}

}  // namespace ts
