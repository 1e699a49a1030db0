#include "sim/scene_mesh.h"

#include <cmath>
#include <map>
#include <numbers>

namespace ts::sim {
namespace {

void AddTriangle(SceneMesh* mesh, int a, int b, int c, Surface surface, int object,
                 const Eigen::Vector3d& outward_hint) {
  const Eigen::Vector3d& pa = mesh->vertices[a];
  Eigen::Vector3d n = (mesh->vertices[b] - pa).cross(mesh->vertices[c] - pa);
  if (n.squaredNorm() == 0.0) return;
  n.normalize();
  if (n.dot(outward_hint) < 0.0) {
    n = -n;
    std::swap(b, c);
  }
  mesh->triangles.emplace_back(a, b, c);
  mesh->normals.push_back(n);
  mesh->plane_offsets.push_back(n.dot(pa));
  mesh->surfaces.push_back(surface);
  mesh->objects.push_back(object);
}

void AddTerrain(const Scene& scene, SceneMesh* mesh) {
  const int n = scene.n;
  mesh->vertices.reserve(static_cast<size_t>(n) * n);
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix)
      mesh->vertices.emplace_back(scene.LatticeX(ix), scene.LatticeX(iy), scene.lattice(ix, iy));
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  for (int iy = 0; iy + 1 < n; ++iy) {
    for (int ix = 0; ix + 1 < n; ++ix) {
      const int v00 = iy * n + ix, v10 = v00 + 1, v01 = v00 + n, v11 = v01 + 1;
      AddTriangle(mesh, v00, v10, v11, Surface::kTerrain, -1, up);  // half 0
      AddTriangle(mesh, v00, v11, v01, Surface::kTerrain, -1, up);  // half 1
    }
  }
  mesh->terrain_triangles = static_cast<int>(mesh->triangles.size());
}

// Unit icosphere: 12 vertices, 20 faces, each subdivision splits every face in four.
void UnitSphere(int subdivisions, std::vector<Eigen::Vector3d>* v,
                std::vector<Eigen::Vector3i>* f) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  *v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
        {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : *v) p.normalize();
  *f = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoints;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = midpoints.try_emplace(key, static_cast<int>(v->size()));
      if (added) v->push_back(((*v)[a] + (*v)[b]).normalized());
      return it->second;
    };
    std::vector<Eigen::Vector3i> next;
    for (const auto& tri : *f) {
      const int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
      next.insert(next.end(), {{tri[0], ab, ca}, {tri[1], bc, ab}, {tri[2], ca, bc}, {ab, bc, ca}});
    }
    *f = std::move(next);
  }
}

void AddObject(const SceneObject& o, int index, SceneMesh* mesh) {
  static std::vector<Eigen::Vector3d> sphere_v;
  static std::vector<Eigen::Vector3i> sphere_f;
  if (sphere_v.empty()) UnitSphere(2, &sphere_v, &sphere_f);
  const int base = static_cast<int>(mesh->vertices.size());
  for (const auto& p : sphere_v)
    mesh->vertices.push_back(o.canopy_centre + p.cwiseProduct(o.canopy_radii_m));
  for (const auto& f : sphere_f) {
    const Eigen::Vector3d centroid =
        (mesh->vertices[base + f[0]] + mesh->vertices[base + f[1]] + mesh->vertices[base + f[2]]) /
        3.0;
    AddTriangle(mesh, base + f[0], base + f[1], base + f[2], Surface::kCanopy, index,
                centroid - o.canopy_centre);
  }
  if (o.kind != ObjectKind::kTree) return;
  constexpr int kSegments = 10;
  const int trunk = static_cast<int>(mesh->vertices.size());
  for (int k = 0; k < kSegments; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kSegments;
    const Eigen::Vector3d radial(o.trunk_radius_m * std::cos(a), o.trunk_radius_m * std::sin(a), 0);
    mesh->vertices.push_back(o.ground + radial - Eigen::Vector3d(0, 0, 0.3));  // into the ground
    mesh->vertices.push_back(o.ground + radial + Eigen::Vector3d(0, 0, o.trunk_height_m));
  }
  for (int k = 0; k < kSegments; ++k) {
    const int a = trunk + 2 * k, b = trunk + 2 * ((k + 1) % kSegments);
    const Eigen::Vector3d out = (mesh->vertices[a] + mesh->vertices[b]) / 2.0 - o.ground;
    const Eigen::Vector3d outward(out.x(), out.y(), 0.0);
    AddTriangle(mesh, a, b, b + 1, Surface::kTrunk, index, outward);
    AddTriangle(mesh, a, b + 1, a + 1, Surface::kTrunk, index, outward);
  }
}

}  // namespace

SceneMesh BuildSceneMesh(const Scene& scene) {
  SceneMesh mesh;
  AddTerrain(scene, &mesh);
  for (size_t i = 0; i < scene.objects.size(); ++i)
    AddObject(scene.objects[i], static_cast<int>(i), &mesh);
  return mesh;
}

}  // namespace ts::sim
