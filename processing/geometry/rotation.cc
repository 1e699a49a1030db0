#include "processing/geometry/rotation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ts {
namespace {
// Below this cos(phi) the first and third axes are treated as aligned (gimbal lock).
constexpr double kGimbalLockCos = 1e-12;
}  // namespace

double DegFromRad(double rad) { return rad * 180.0 / std::numbers::pi; }
double RadFromDeg(double deg) { return deg * std::numbers::pi / 180.0; }

Eigen::Matrix3d RotationFromOpk(const Opk& opk) {
  return RotationX(opk.omega_rad) * RotationY(opk.phi_rad) * RotationZ(opk.kappa_rad);
}

Opk OpkFromRotation(const Eigen::Matrix3d& r) {
  // R = Rx Ry Rz has R02 = sin(phi), R12 = -sin(omega) cos(phi), R22 = cos(omega) cos(phi),
  // R01 = -cos(phi) sin(kappa), R00 = cos(phi) cos(kappa).
  Opk opk;
  opk.phi_rad = std::asin(std::clamp(r(0, 2), -1.0, 1.0));
  if (std::hypot(r(0, 0), r(0, 1)) > kGimbalLockCos) {
    opk.omega_rad = std::atan2(-r(1, 2), r(2, 2));
    opk.kappa_rad = std::atan2(-r(0, 1), r(0, 0));
  } else {
    opk.omega_rad = std::atan2(r(2, 1), r(1, 1));
    opk.kappa_rad = 0.0;
  }
  return opk;
}

Eigen::Matrix3d RotationFromOpkDeg(const Eigen::Vector3d& deg) {
  return RotationFromOpk({RadFromDeg(deg.x()), RadFromDeg(deg.y()), RadFromDeg(deg.z())});
}

Eigen::Vector3d OpkDegFromRotation(const Eigen::Matrix3d& rotation) {
  const Opk opk = OpkFromRotation(rotation);
  return {DegFromRad(opk.omega_rad), DegFromRad(opk.phi_rad), DegFromRad(opk.kappa_rad)};
}

Eigen::Matrix3d RotationFromAzElRoll(const AzElRoll& a) {
  const double ct = std::cos(a.azimuth_rad), st = std::sin(a.azimuth_rad);
  const double cp = std::cos(a.elevation_rad), sp = std::sin(a.elevation_rad);
  const double ck = std::cos(a.roll_rad), sk = std::sin(a.roll_rad);
  Eigen::Matrix3d m;
  m << ck * ct - sk * sp * st, sk * cp, -ck * st - sk * sp * ct,  //
      -sk * ct - ck * sp * st, ck * cp, sk * st - ck * sp * ct,   //
      cp * st, sp, cp * ct;
  return m;
}

AzElRoll AzElRollFromRotation(const Eigen::Matrix3d& m) {
  // m32 = sin(phi), m31 = cos(phi) sin(theta), m33 = cos(phi) cos(theta),
  // m12 = sin(kappa) cos(phi), m22 = cos(kappa) cos(phi).
  AzElRoll a;
  a.elevation_rad = std::asin(std::clamp(m(2, 1), -1.0, 1.0));
  if (std::hypot(m(2, 0), m(2, 2)) > kGimbalLockCos) {
    a.azimuth_rad = std::atan2(m(2, 0), m(2, 2));
    a.roll_rad = std::atan2(m(0, 1), m(1, 1));
  } else {
    // cos(phi) = 0: only theta -/+ kappa is defined; put it all into theta.
    a.roll_rad = 0.0;
    a.azimuth_rad = std::atan2(-m(0, 2), m(0, 0));
  }
  return a;
}

}  // namespace ts
