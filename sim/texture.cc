#include "sim/texture.h"

#include <algorithm>
#include <cmath>

#include "sim/noise.h"

namespace ts::sim {

namespace {
// Ground detail from 2 m down to 1 cm; octaves 0-2 (2, 1, 0.5 m) are the coarse part.
constexpr int kCoarseOctaves = 3;
const FractalPlan kPatchPlan({12.0, 1.5, 0.55});
const FractalPlan kCoarsePlan({2.0, 0.01, 0.78, 0, kCoarseOctaves});
const FractalPlan kFinePlan({2.0, 0.01, 0.78, kCoarseOctaves});
const FractalPlan kBarkPlan({1.0, 0.02, 0.7});
const FractalPlan kLeafPlan({1.0, 0.01, 0.8});
}  // namespace

GroundMaterial GroundMaterialAt(uint64_t seed, double x, double y, double footprint_m) {
  // 0 = grass, 1 = bare soil, from slow noise with a soft threshold. Its shortest octave
  // (1.5 m) is far coarser than any pixel, so it needs no footprint.
  const double patch = Fractal2(seed ^ 0xA1, x, y, 1e-9, kPatchPlan);
  const double soil = std::clamp(0.5 + 2.5 * patch, 0.0, 1.0);
  return {0.20 + 0.14 * soil, 0.9 - 0.3 * soil,
          Fractal2(seed ^ 0xB2, x, y, footprint_m, kCoarsePlan)};
}

double GroundAlbedo(uint64_t seed, const GroundMaterial& m, double x, double y,
                    double footprint_m) {
  const double detail = m.coarse + Fractal2(seed ^ 0xB2, x, y, footprint_m, kFinePlan);
  // Multiplicative detail (exp keeps it positive without clipping dark tails to black).
  return std::min(1.0, m.base * std::exp(1.2 * m.contrast * detail));
}

double ObjectAlbedo(uint64_t seed, Surface surface, const Eigen::Vector3d& p, double footprint_m) {
  if (surface == Surface::kTrunk) {
    const double bark =
        Fractal3(seed ^ 0xC3, 8.0 * p.x(), 8.0 * p.y(), 0.5 * p.z(), footprint_m, kBarkPlan);
    return std::min(1.0, 0.18 * std::exp(1.2 * bark));
  }
  const double leaves = Fractal3(seed ^ 0xD4, p.x(), p.y(), p.z(), footprint_m, kLeafPlan);
  return std::min(1.0, 0.12 * std::exp(1.8 * leaves));
}

}  // namespace ts::sim
