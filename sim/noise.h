#pragma once
// Procedural noise for the simulated world: hashed value noise (no period at any scale a
// scene uses, so there is no tile a matcher could lock onto) and band-limited fractal sums.
// Pure functions of (seed, position): the same world point looks the same from every camera.
#include <cmath>
#include <cstdint>
#include <vector>

namespace ts::sim {

// 64-bit mix of the lattice coordinates and the seed (SplitMix64 finaliser).
inline uint64_t Hash(uint64_t seed, int64_t i, int64_t j, int64_t k = 0) {
  uint64_t h = seed ^ (static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^
               (static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4Full) ^
               (static_cast<uint64_t>(k) * 0x165667B19E3779F9ull);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBull;
  h ^= h >> 31;
  return h;
}

// Uniform in [-1, 1).
inline double HashUnit(uint64_t seed, int64_t i, int64_t j, int64_t k = 0) {
  return static_cast<double>(Hash(seed, i, j, k) >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

// Standard normal (Box-Muller on two hashes): a draw that depends on its indices alone.
inline double HashGaussian(uint64_t seed, int64_t i, int64_t j, int64_t k = 0) {
  const double u1 = (static_cast<double>(Hash(seed, i, j, 2 * k) >> 11) + 1.0) / 9007199254740993.0;
  const double u2 = static_cast<double>(Hash(seed, i, j, 2 * k + 1) >> 11) / 9007199254740992.0;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

// Cheap 32-bit lattice hash for the noise functions (lowbias32 finaliser), in [-1, 1).
inline double LatticeValue(uint32_t seed, int32_t i, int32_t j, int32_t k = 0) {
  uint32_t h = seed ^ (static_cast<uint32_t>(i) * 0x27D4EB2Du) ^
               (static_cast<uint32_t>(j) * 0x165667B1u) ^ (static_cast<uint32_t>(k) * 0x9E3779B9u);
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return static_cast<double>(h) * (2.0 / 4294967296.0) - 1.0;
}

// Value noise with quintic interpolation (C2), unit lattice, range about [-1, 1].
double ValueNoise2(uint64_t seed, double x, double y);
double ValueNoise3(uint64_t seed, double x, double y, double z);

// Sum of octaves of value noise from wavelength `longest_m` down to `shortest_m` (halving,
// amplitude times `gain` per octave). Octaves shorter than twice `footprint_m` (the size of
// the pixel on the surface) fade out, which band-limits the texture to what a pixel can
// resolve: the anti-aliasing of the renderer. Normalised to a standard deviation of ~0.3.
struct FractalOptions {
  double longest_m = 4.0;
  double shortest_m = 0.01;
  double gain = 0.7;
  // Evaluate only octaves [first_octave, first_octave + octave_count) (0 = longest). The
  // normalisation is over all octaves, so partial sums over disjoint ranges add up to the
  // full sum: a caller may evaluate slow octaves once per pixel and fast ones per probe.
  int first_octave = 0;
  int octave_count = 64;
};

// The octaves of a FractalOptions, computed once: wavelengths, frequencies, rotations,
// amplitudes and the normalisation. Build one per texture (static) and pass it per sample.
class FractalPlan {
 public:
  explicit FractalPlan(const FractalOptions& options);
  struct Octave {
    int index;  // octave number, 0 = longest
    double wavelength_m, frequency, amplitude, cos_angle, sin_angle, offset_x, offset_y;
  };
  std::vector<Octave> octaves;  // only those in [first_octave, first_octave + octave_count)
  double inverse_norm = 1.0;
};

double Fractal2(uint64_t seed, double x, double y, double footprint_m, const FractalPlan& plan);
double Fractal3(uint64_t seed, double x, double y, double z, double footprint_m,
                const FractalPlan& plan);
// Convenience for one-off use (builds the plan each call).
inline double Fractal2(uint64_t seed, double x, double y, double footprint_m,
                       const FractalOptions& o) {
  return Fractal2(seed, x, y, footprint_m, FractalPlan(o));
}

// Smooth fractal relief of a scene between two wavelengths (all octaves, no footprint cut).
inline double Relief(uint64_t seed, double x, double y, double longest_m, double shortest_m,
                     double gain = 0.5) {
  return Fractal2(seed, x, y, 1e-9, {longest_m, shortest_m, gain});
}

// 0 below 0, 1 above 1, a cubic with level ends between: a ramp without kinks.
inline double Smoothstep(double t) {
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace ts::sim
