#pragma once
// Distance along a unit ray to a simulated scene's terrain, by marching (2 cm steps) and
// bisection: an answer that knows nothing of meshes, rasterisation or the renderer.
#include <Eigen/Core>
#include <cmath>

#include "sim/scene.h"

namespace ts::testing {

inline double MarchToTerrain(const sim::Scene& s, const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& ray) {
  double t0 = 0.0;
  for (double t = 0.02; t < 200.0; t += 0.02) {
    const Eigen::Vector3d p = origin + t * ray;
    const double h = s.TerrainHeight(p.x(), p.y());
    if (std::isnan(h)) return NAN;
    if (p.z() <= h) {
      double a = t0, b = t;
      for (int i = 0; i < 60; ++i) {
        const double m = 0.5 * (a + b);
        const Eigen::Vector3d q = origin + m * ray;
        (q.z() <= s.TerrainHeight(q.x(), q.y()) ? b : a) = m;
      }
      return 0.5 * (a + b);
    }
    t0 = t;
  }
  return NAN;
}

}  // namespace ts::testing
