#pragma once
// A simulated station site, everything in the station frame L (DESIGN.md): origin at the
// stage centre, Z up, so the station mark (the ground under the tripod) is at (0, 0, -h).
//
// Bare earth is a height lattice (spacing 0.25 m) triangulated along one diagonal per cell;
// TerrainHeight() evaluates exactly that surface, so the renderer and the ground truth agree
// to the last bit. Trees and bushes are separate 3D objects above the ground.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts::sim {

enum class ObjectKind { kTree, kBush };

struct SceneObject {
  ObjectKind kind = ObjectKind::kTree;
  Eigen::Vector3d ground;          // ground point under the object's axis
  double trunk_radius_m = 0.0;     // trees only
  double trunk_height_m = 0.0;     // trees only: from the ground to the canopy centre
  Eigen::Vector3d canopy_centre;   // ellipsoid centre
  Eigen::Vector3d canopy_radii_m;  // ellipsoid semi-axes (x, y, z)
  // True where the object's vertical footprint covers (x, y).
  bool Covers(double x_m, double y_m) const;
};

// Unit vector towards a sun at an azimuth (radians clockwise from north = +Y) and elevation.
Eigen::Vector3d SunDirection(double azimuth_rad, double elevation_rad);

struct Lighting {
  Eigen::Vector3d to_sun = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();  // unit, towards sun
  double ambient = 0.35;  // sky light, fraction of a sunlit horizontal surface
  double direct = 0.65;
};

// A subsidence bowl that formed between two epochs: the ground sinks by
// depth * (1 + cos(pi r / radius)) / 2 within `radius` of the centre (a raised-cosine bowl:
// smooth, compact, with a closed-form volume (1/2 - 2/pi^2) pi depth radius^2).
struct Subsidence {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
  double depth_m = 0.0;
  double LoweringAt(double x_m, double y_m) const;
  double Volume() const;
};

struct Scene {
  std::string name;
  uint64_t seed = 0;
  int epoch = 1;  // a later survey of the same site: the same ground, new sensor noise
  std::vector<Subsidence> subsidence;  // applied to heights and objects since epoch 1
  double stage_height_m = 1.5;         // h: stage centre above the station mark
  // Height lattice: heights[iy * n + ix] at x = -half_extent_m + ix * spacing_m (same for y).
  double half_extent_m = 60.0;
  double spacing_m = 0.25;
  int n = 0;
  std::vector<float> heights;
  std::vector<SceneObject> objects;
  Lighting lighting;

  double LatticeX(int ix) const { return -half_extent_m + ix * spacing_m; }
  float& lattice(int ix, int iy) { return heights[static_cast<size_t>(iy) * n + ix]; }
  float lattice(int ix, int iy) const { return heights[static_cast<size_t>(iy) * n + ix]; }
  // Height of the triangulated bare earth; NaN outside the lattice.
  double TerrainHeight(double x_m, double y_m) const;
  // Triangle of the lattice containing (x, y): cell (ix, iy) and which half (0: x-frac >=
  // y-frac, the triangle (ix,iy)-(ix+1,iy)-(ix+1,iy+1)); false outside.
  bool LocateTriangle(double x_m, double y_m, int* ix, int* iy, int* half) const;
  bool ObjectCovers(double x_m, double y_m) const;
};

// Names of the built-in scenes: flat, hills, slope, rough, forest, and the landforms
// embankment, terraces, foot, ridge, badlands (scene_landforms.h).
const std::vector<std::string>& BuiltinSceneNames();
// A built-in scene; deterministic for (name, seed). Error for an unknown name.
Result<Scene> MakeBuiltinScene(const std::string& name, uint64_t seed);
// Terrain from any GeoTIFF DEM, centred on the DEM's centre (the station), re-levelled so the
// ground at the station is at -stage_height_m. No objects.
Result<Scene> MakeSceneFromDem(const std::string& dem_file, uint64_t seed);

// Sinks the ground (lattice and the objects standing on it) by the bowl; an error if the bowl
// reaches the station mark, to which the station frame is tied.
Status ApplySubsidence(Scene* scene, const Subsidence& bowl);
// The sun at an azimuth (degrees clockwise from north = +Y) and elevation above the horizon.
Status SetSun(Scene* scene, double azimuth_deg, double elevation_deg);

// Fills the lattice from a height function H(x, y) and shifts it so H(0, 0) = -stage height.
template <typename HeightFn>
void FillLattice(Scene* scene, HeightFn height) {
  scene->n = static_cast<int>(std::lround(2.0 * scene->half_extent_m / scene->spacing_m)) + 1;
  scene->heights.resize(static_cast<size_t>(scene->n) * scene->n);
  const double h0 = height(0.0, 0.0);
  for (int iy = 0; iy < scene->n; ++iy)
    for (int ix = 0; ix < scene->n; ++ix)
      scene->lattice(ix, iy) = static_cast<float>(height(scene->LatticeX(ix), scene->LatticeX(iy)) -
                                                  h0 - scene->stage_height_m);
}

}  // namespace ts::sim
