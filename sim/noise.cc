#include "sim/noise.h"

#include <cmath>

namespace ts::sim {
namespace {

// floor() for the coordinates the noise sees (|x| < 2^31): much cheaper than std::floor.
inline int32_t FastFloor(double x) {
  const int32_t i = static_cast<int32_t>(x);
  return x < i ? i - 1 : i;
}

inline double Fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
inline double Lerp(double a, double b, double t) { return a + t * (b - a); }

// 0 when the octave is shorter than two footprints, 1 from four footprints up, smooth between.
inline double OctaveWeight(double wavelength, double inverse_footprint) {
  const double t = (wavelength * inverse_footprint - 2.0) * 0.5;
  if (t <= 0.0) return 0.0;
  if (t >= 1.0) return 1.0;
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace

double ValueNoise2(uint64_t seed, double x, double y) {
  const int32_t i = FastFloor(x), j = FastFloor(y);
  const double fx = i, fy = j;
  const uint32_t s = static_cast<uint32_t>(seed ^ (seed >> 32));
  const double tx = Fade(x - fx), ty = Fade(y - fy);
  const double a = LatticeValue(s, i, j), b = LatticeValue(s, i + 1, j);
  const double c = LatticeValue(s, i, j + 1), d = LatticeValue(s, i + 1, j + 1);
  return Lerp(Lerp(a, b, tx), Lerp(c, d, tx), ty);
}

double ValueNoise3(uint64_t seed, double x, double y, double z) {
  const int32_t i = FastFloor(x), j = FastFloor(y), k = FastFloor(z);
  const double fx = i, fy = j, fz = k;
  const uint32_t s = static_cast<uint32_t>(seed ^ (seed >> 32));
  const double tx = Fade(x - fx), ty = Fade(y - fy), tz = Fade(z - fz);
  double plane[2];
  for (int dz = 0; dz < 2; ++dz) {
    const double a = LatticeValue(s, i, j, k + dz), b = LatticeValue(s, i + 1, j, k + dz);
    const double c = LatticeValue(s, i, j + 1, k + dz), d = LatticeValue(s, i + 1, j + 1, k + dz);
    plane[dz] = Lerp(Lerp(a, b, tx), Lerp(c, d, tx), ty);
  }
  return Lerp(plane[0], plane[1], tz);
}

FractalPlan::FractalPlan(const FractalOptions& o) {
  double norm = 0.0, amplitude = 1.0;
  int index = 0;
  for (double w = o.longest_m; w >= o.shortest_m * 0.999; w *= 0.5, amplitude *= o.gain, ++index) {
    norm += amplitude * amplitude;
    if (index < o.first_octave || index >= o.first_octave + o.octave_count) continue;
    // A rotation and offset per octave keep lattice axes and origins from lining up.
    const double angle = 0.61 * index;
    octaves.push_back({index, w, 1.0 / w, amplitude, std::cos(angle), std::sin(angle), 17.3 * index,
                       -9.1 * index});
  }
  // Value noise has a standard deviation of about 0.3 per octave; the sum is normalised over
  // all octaves, so a footprint cut removes the cut octaves' variance, as blur would.
  inverse_norm = norm > 0.0 ? 1.0 / std::sqrt(norm) : 0.0;
}

double Fractal2(uint64_t seed, double x, double y, double footprint_m, const FractalPlan& plan) {
  const double inverse_footprint = 1.0 / footprint_m;
  double sum = 0.0;
  for (const FractalPlan::Octave& o : plan.octaves) {
    const double weight = OctaveWeight(o.wavelength_m, inverse_footprint);
    if (weight <= 0.0) break;  // shorter octaves are cut too
    const double u = o.frequency * (o.cos_angle * x - o.sin_angle * y) + o.offset_x;
    const double v = o.frequency * (o.sin_angle * x + o.cos_angle * y) + o.offset_y;
    sum += weight * o.amplitude * ValueNoise2(seed + o.index, u, v);
  }
  return sum * plan.inverse_norm;
}

double Fractal3(uint64_t seed, double x, double y, double z, double footprint_m,
                const FractalPlan& plan) {
  const double inverse_footprint = 1.0 / footprint_m;
  double sum = 0.0;
  for (const FractalPlan::Octave& o : plan.octaves) {
    const double weight = OctaveWeight(o.wavelength_m, inverse_footprint);
    if (weight <= 0.0) break;
    sum += weight * o.amplitude *
           ValueNoise3(seed + o.index, o.frequency * x + o.offset_x, o.frequency * y + o.offset_y,
                       o.frequency * z + 3.7 * o.index);
  }
  return sum * plan.inverse_norm;
}

}  // namespace ts::sim
