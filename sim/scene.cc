#include "sim/scene.h"

#include <cmath>

namespace ts::sim {

Eigen::Vector3d SunDirection(double az, double el) {
  return Eigen::Vector3d(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
}

bool SceneObject::Covers(double x_m, double y_m) const {
  const double dx = (x_m - canopy_centre.x()) / canopy_radii_m.x();
  const double dy = (y_m - canopy_centre.y()) / canopy_radii_m.y();
  if (dx * dx + dy * dy <= 1.0) return true;
  if (kind == ObjectKind::kTree) {
    const double tx = x_m - ground.x(), ty = y_m - ground.y();
    return tx * tx + ty * ty <= trunk_radius_m * trunk_radius_m;
  }
  return false;
}

bool Scene::LocateTriangle(double x_m, double y_m, int* ix, int* iy, int* half) const {
  const double fx = (x_m + half_extent_m) / spacing_m, fy = (y_m + half_extent_m) / spacing_m;
  if (!(fx >= 0.0) || !(fy >= 0.0) || fx > n - 1 || fy > n - 1) return false;
  *ix = std::min(static_cast<int>(fx), n - 2);
  *iy = std::min(static_cast<int>(fy), n - 2);
  *half = (fx - *ix) >= (fy - *iy) ? 0 : 1;
  return true;
}

double Scene::TerrainHeight(double x_m, double y_m) const {
  int ix, iy, half;
  if (!LocateTriangle(x_m, y_m, &ix, &iy, &half)) return std::nan("");
  const double tx = (x_m + half_extent_m) / spacing_m - ix;
  const double ty = (y_m + half_extent_m) / spacing_m - iy;
  const double h00 = lattice(ix, iy), h11 = lattice(ix + 1, iy + 1);
  if (half == 0) {  // (0,0) (1,0) (1,1)
    const double h10 = lattice(ix + 1, iy);
    return h00 + tx * (h10 - h00) + ty * (h11 - h10);
  }
  const double h01 = lattice(ix, iy + 1);  // (0,0) (1,1) (0,1)
  return h00 + ty * (h01 - h00) + tx * (h11 - h01);
}

bool Scene::ObjectCovers(double x_m, double y_m) const {
  for (const SceneObject& o : objects)
    if (o.Covers(x_m, y_m)) return true;
  return false;
}

}  // namespace ts::sim
