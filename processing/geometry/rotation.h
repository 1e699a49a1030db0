#pragma once
// Rotation conventions. All angles here are radians; configs carry degrees (`_deg`).
//
// Elementary rotations are active and right-handed: RotationZ(a) turns +X towards +Y.
//
// Omega-phi-kappa (photogrammetric, e.g. Kraus): R = Rx(omega) * Ry(phi) * Rz(kappa).
// Used for small mounting angles and relative orientations; R maps the rotated frame's
// vectors into the reference frame (reference_from_rotated).
//
// Azimuth-elevation-roll of seed 004 (Wu 2009, eqs. 2-3): M = m_kappa * m_phi * m_theta,
// camera_from_world in its collinearity x = dx - c (m1 . dX) / (m3 . dX). We implement the
// explicit elements of its eq. 3b. Note that eq. 3b equals Rz(-kappa) Rx(phi) Ry(-theta):
// the m_theta printed as eq. 2a has the opposite sign of theta; 3b is what the collinearity
// uses, so 3b is the definition here (tested element by element).
#include <Eigen/Core>
#include <cmath>
#include <numbers>

namespace ts {

// Templated so that Ceres can differentiate through them (stage_kinematics.h).
template <typename T>
Eigen::Matrix<T, 3, 3> RotationX(const T& a) {
  using std::cos, std::sin;
  const T c = cos(a), s = sin(a), o(0), i(1);
  Eigen::Matrix<T, 3, 3> r;
  r << i, o, o, o, c, -s, o, s, c;
  return r;
}
template <typename T>
Eigen::Matrix<T, 3, 3> RotationY(const T& a) {
  using std::cos, std::sin;
  const T c = cos(a), s = sin(a), o(0), i(1);
  Eigen::Matrix<T, 3, 3> r;
  r << c, o, s, o, i, o, -s, o, c;
  return r;
}
template <typename T>
Eigen::Matrix<T, 3, 3> RotationZ(const T& a) {
  using std::cos, std::sin;
  const T c = cos(a), s = sin(a), o(0), i(1);
  Eigen::Matrix<T, 3, 3> r;
  r << c, -s, o, s, c, o, o, o, i;
  return r;
}

struct Opk {
  double omega_rad = 0.0;
  double phi_rad = 0.0;
  double kappa_rad = 0.0;
};

Eigen::Matrix3d RotationFromOpk(const Opk& opk);
// Inverse of RotationFromOpk for phi in [-pi/2, pi/2]. At gimbal lock (|phi| = pi/2)
// kappa is set to 0 and the whole rotation about the common axis goes into omega.
Opk OpkFromRotation(const Eigen::Matrix3d& rotation);

// The same with the angles in degrees, as configs and calibration files carry them; templated
// so that Ceres can differentiate it.
template <typename T>
Eigen::Matrix<T, 3, 3> RotationFromOpkDeg(const T& omega, const T& phi, const T& kappa) {
  const T rad(std::numbers::pi / 180.0);
  return RotationX(omega * rad) * RotationY(phi * rad) * RotationZ(kappa * rad);
}
Eigen::Matrix3d RotationFromOpkDeg(const Eigen::Vector3d& deg);
Eigen::Vector3d OpkDegFromRotation(const Eigen::Matrix3d& rotation);

struct AzElRoll {
  double azimuth_rad = 0.0;    // theta: about the vertical axis, to the right positive
  double elevation_rad = 0.0;  // phi: about the horizontal axis, upward positive
  double roll_rad = 0.0;       // kappa: about the viewing axis, counter-clockwise positive
};

// Seed 004 eq. 3b.
Eigen::Matrix3d RotationFromAzElRoll(const AzElRoll& angles);
// Inverse for elevation in [-pi/2, pi/2]; at gimbal lock roll is set to 0.
AzElRoll AzElRollFromRotation(const Eigen::Matrix3d& rotation);

double DegFromRad(double rad);
double RadFromDeg(double deg);

}  // namespace ts
