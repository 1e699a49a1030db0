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

// Weight of an octave of wavelength w seen through a footprint f: 1 when w >= 4f, 0 when
// w <= 2f, smooth in between.
inline double OctaveWeight(double wavelength, double footprint) {
  const double t = (wavelength / footprint - 2.0) * 0.5;
  if (t <= 0.0) return 0.0;
  if (t >= 1.0) return 1.0;
  return t * t * (3.0 - 2.0 * t);
}

constexpr int kMaxOctaves = 24;
struct OctaveRotations {
  double cos[kMaxOctaves], sin[kMaxOctaves];
  OctaveRotations() {
    for (int i = 0; i < kMaxOctaves; ++i) {
      cos[i] = std::cos(0.61 * i);
      sin[i] = std::sin(0.61 * i);
    }
  }
};

template <typename Octave>
double SumOctaves(double footprint_m, const FractalOptions& o, Octave octave) {
  double sum = 0.0, norm = 0.0, amplitude = 1.0;
  const int end = o.first_octave + o.octave_count;
  bool cut = false;
  int index = 0;
  for (double w = o.longest_m; w >= o.shortest_m * 0.999; w *= 0.5, amplitude *= o.gain, ++index) {
    norm += amplitude * amplitude;
    if (cut || index < o.first_octave || index >= end) continue;
    const double weight = OctaveWeight(w, footprint_m);
    if (weight <= 0.0) {
      cut = true;  // shorter octaves are cut too
      continue;
    }
    sum += weight * amplitude * octave(1.0 / w, index);
  }
  // Value noise has a standard deviation of about 0.3 per octave; keep the sum comparable
  // whether or not short octaves were cut (the cut removes their variance, as blur would).
  return norm > 0.0 ? sum / std::sqrt(norm) : 0.0;
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

double Fractal2(uint64_t seed, double x, double y, double footprint_m, const FractalOptions& o) {
  return SumOctaves(footprint_m, o, [&](double frequency, int index) {
    // A rotation per octave keeps lattice axes from lining up across octaves.
    static const OctaveRotations rotations;
    const double c = rotations.cos[index % kMaxOctaves], s = rotations.sin[index % kMaxOctaves];
    return ValueNoise2(seed + index, frequency * (c * x - s * y) + 17.3 * index,
                       frequency * (s * x + c * y) - 9.1 * index);
  });
}

double Fractal3(uint64_t seed, double x, double y, double z, double footprint_m,
                const FractalOptions& o) {
  return SumOctaves(footprint_m, o, [&](double frequency, int index) {
    return ValueNoise3(seed + index, frequency * x + 17.3 * index, frequency * y - 9.1 * index,
                       frequency * z + 3.7 * index);
  });
}

}  // namespace ts::sim
