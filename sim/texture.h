#pragma once
// Surface reflectance of the simulated world (albedo in [0, 1]), band-limited to the pixel
// footprint on the surface so that no texture detail finer than a pixel can alias.
//   Ground: grass and soil patches (metres), clumps and stones (decimetres) and grain down to
//   1 cm, from hashed noise: nothing repeats.
//   Canopy: leaf clusters (3D noise); trunk: vertical bark streaks.
#include <Eigen/Core>
#include <cstdint>

#include "sim/scene_mesh.h"

namespace ts::sim {

// The slowly varying part of the ground at a point: the material (grass or soil, metres) and
// the detail octaves of 0.5 m and longer. Evaluate once per pixel and share between probes.
struct GroundMaterial {
  double base = 0.25;     // mean albedo
  double contrast = 0.7;  // relative amplitude of the detail
  double coarse = 0.0;    // detail octaves >= 0.5 m
};
GroundMaterial GroundMaterialAt(uint64_t seed, double x_m, double y_m, double footprint_m);
double GroundAlbedo(uint64_t seed, const GroundMaterial& material, double x_m, double y_m,
                    double footprint_m);
double ObjectAlbedo(uint64_t seed, Surface surface, const Eigen::Vector3d& point_m,
                    double footprint_m);

}  // namespace ts::sim
