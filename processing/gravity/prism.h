#pragma once
// Gravitational attraction of a homogeneous rectangular prism: the closed form of Nagy (1966)
// for the vertical component, in a form that is safe at every point (seed-free: standard
// potential theory, e.g. Blakely 1995 sec. 9.3). With the prism [x1, x2] x [y1, y2] x [z1, z2]
// given relative to the point of observation (z up),
//   g_up = G rho sum_{i,j,k} (-1)^{i+j+k} [ x ln(y + r) + y ln(x + r) - z atan(x y / (z r)) ]
// over the eight corners (x_i, y_j, z_k), r = |(x, y, z)|. Kept finite and accurate:
//  - the two ends of each vertical edge are differenced analytically (log1p of the ratio),
//    so a prism far wider than deep (a slab) does not cancel huge logarithms;
//  - ln(y + r) for y < 0 is taken as ln((x^2 + z^2) / (r - y)) (no cancellation), and a term
//    whose factor is 0 is 0 (the limit x ln(...) -> 0 on edges and faces);
//  - z atan(x y / (z r)) is 0 for z = 0 (its limit), the principal value otherwise.
// The result is the DOWNWARD attraction -g_up (m/s^2): positive for mass below the point.
#include <Eigen/Core>

namespace ts {

inline constexpr double kGravitationalConstant = 6.6743e-11;  // m^3 kg^-1 s^-2 (CODATA 2018)
inline constexpr double kStandardDensityKgM3 = 2670.0;        // the standard crustal density
inline constexpr double kMgalPerMs2 = 1e5;                    // 1 mGal = 1e-5 m/s^2

// Downward attraction at the origin of the prism between the two corners (relative to the
// point of observation, metres; min < max on every axis), density in kg/m^3.
double PrismDownwardAttraction(const Eigen::Vector3d& min_corner_m,
                               const Eigen::Vector3d& max_corner_m, double density_kg_m3);

// The far-field form: the prism's mass as four vertical lines at the 2 x 2 Gauss-Legendre
// points of its cross-section, each
//   g_down = -G rho A/4 (1 / sqrt(r^2 + z1^2) - 1 / sqrt(r^2 + z2^2)),
// r the line's horizontal distance. Relative error < 1e-4 at 5 sides, < 1e-5 at 10, then
// falling as (side / r)^4 (one line through the centre: 3e-3 at 10 sides; prism_test).
double PrismDownwardAttractionFarField(const Eigen::Vector3d& min_corner_m,
                                       const Eigen::Vector3d& max_corner_m, double density_kg_m3);

}  // namespace ts
