#pragma once
// The scene as triangles for the rasteriser: the terrain lattice first (two triangles per
// cell, in lattice order, so a triangle's index follows from Scene::LocateTriangle), then the
// trees and bushes (ellipsoid canopies from a subdivided icosahedron, cylindrical trunks).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sim/scene.h"

namespace ts::sim {

enum class Surface : uint8_t { kTerrain, kCanopy, kTrunk };

struct SceneMesh {
  std::vector<Eigen::Vector3d> vertices;   // in L
  std::vector<Eigen::Vector3i> triangles;  // vertex indices
  std::vector<Eigen::Vector3d> normals;    // unit, outward (terrain: upward)
  std::vector<double> plane_offsets;       // n . p for points p on the triangle
  std::vector<Surface> surfaces;
  std::vector<int32_t> objects;  // index into Scene::objects, -1 for terrain
  int terrain_triangles = 0;

  // Index of terrain triangle (ix, iy, half), see Scene::LocateTriangle.
  static int TerrainTriangle(const Scene& scene, int ix, int iy, int half) {
    return 2 * (iy * (scene.n - 1) + ix) + half;
  }
};

SceneMesh BuildSceneMesh(const Scene& scene);

}  // namespace ts::sim
