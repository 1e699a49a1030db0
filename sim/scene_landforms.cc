// The landform scenes of issue 22: ground where gravity stations stand and where the near
// terrain hides part of itself from a tripod (embankments and their ditches, terrace risers,
// the gullies of a slope above the station, the flanks below a crest, badland gullies). Each
// is a height function of (x, y) in metres; all randomness comes from the seed, so every seed
// gives another site of the same kind.
#include "sim/scene_landforms.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/noise.h"

namespace ts::sim {
namespace {

double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A direction from the station: u along it, v across it.
struct Frame {
  double c, s;
  double U(double x, double y) const { return c * x + s * y; }
  double V(double x, double y) const { return -s * x + c * y; }
};

Frame RandomFrame(std::mt19937_64& rng) {
  const double a = Uniform(rng, 0.0, 2.0 * std::numbers::pi);
  return {std::cos(a), std::sin(a)};
}

// Gently undulating fields with a road on an embankment across them: its near toe 6-8 m from
// the station, 1.5-2.5 m high (varying slowly along it), a 7 m crown, side slopes 1:1.5, and
// a ditch 0.6-1 m deep beyond its far toe.
void Embankment(uint64_t s, std::mt19937_64& rng, Scene* scene) {
  const Frame f = RandomFrame(rng);
  const double near_toe = Uniform(rng, 6.0, 8.0), crown_half = 3.5, batter = 1.5;
  const double mean_height = Uniform(rng, 1.7, 2.3), ditch_depth = Uniform(rng, 0.6, 1.0);
  const double grade = Uniform(rng, -0.01, 0.01);
  FillLattice(scene, [&](double x, double y) {
    const double u = f.U(x, y), v = f.V(x, y);
    const double ground = 0.3 * Relief(s, x, y, 40.0, 8.0) + grade * v;
    const double height =
        std::clamp(mean_height + 0.6 * Relief(s + 3, v, 0.0, 60.0, 30.0), 1.5, 2.5);
    const double centre = near_toe + batter * height + crown_half;
    const double from_centre = std::abs(u - centre);
    const double road =
        height *
        std::clamp((crown_half + batter * height - from_centre) / (batter * height), 0.0, 1.0);
    const double ditch_centre = centre + crown_half + batter * height + 1.5;
    const double ditch = ditch_depth * std::max(0.0, 1.0 - std::abs(u - ditch_centre) / 1.0);
    return ground + road - ditch;
  });
}

// Agricultural terraces on a hillside: treads 5-8 m wide, each riser 1-2 m high over 0.6 m,
// the contours wavy; the station in the middle of a tread, so that the risers above it are
// seen from below and those below it hidden from above.
void Terraces(uint64_t s, std::mt19937_64& rng, Scene* scene) {
  const Frame f = RandomFrame(rng);
  const double tread = Uniform(rng, 5.0, 8.0), riser_width = 0.6;
  const uint64_t risers = Hash(s, 11, 13);
  const auto riser_height = [&](int64_t k) { return 1.5 + 0.5 * HashUnit(risers, k, 0); };
  FillLattice(scene, [&](double x, double y) {
    // Contours bend with the hillside; the station's tread is centred on it.
    const double u = f.U(x, y) + 2.5 * Relief(s + 5, x, y, 80.0, 30.0) -
                     2.5 * Relief(s + 5, 0.0, 0.0, 80.0, 30.0) + 0.5 * tread;
    const double t = u / tread;
    const int64_t k = static_cast<int64_t>(std::floor(t));
    double h = 0.0;  // the risers between tread 0 and tread k
    for (int64_t i = 1; i <= k; ++i) h += riser_height(i);
    for (int64_t i = k + 1; i <= 0; ++i) h -= riser_height(i);
    const double into_riser = (t - k) * tread - (tread - riser_width);
    h += riser_height(k + 1) * Smoothstep(into_riser / riser_width);
    return h + 0.08 * Relief(s, x, y, 20.0, 2.0);
  });
}

// The station at the foot of a slope that rises 25-40 m within 30 m (the steepest ground a
// field team sets up below), cut by gullies along its fall line that deepen uphill; the ground
// behind the station falls away gently.
void Foot(uint64_t s, std::mt19937_64& rng, Scene* scene) {
  const Frame f = RandomFrame(rng);
  const double rise = Uniform(rng, 25.0, 40.0), foot = Uniform(rng, 1.0, 2.0), toe = 3.0;
  const double grade = rise / (30.0 - foot);       // over the toe's rounding, about the rise
  const double spacing = Uniform(rng, 8.0, 12.0);  // of the gullies across the slope
  const uint64_t gullies = Hash(s, 7, 7);
  FillLattice(scene, [&](double x, double y) {
    const double u = f.U(x, y), v = f.V(x, y);
    // A concave toe (radius `toe`), straight up the slope, easing to half beyond 30 m.
    const double climb = std::max(0.0, u - foot);
    const double up = grade * (std::hypot(climb, toe) - toe);
    const double beyond = 30.0 - foot;
    const double slope =
        climb < beyond ? up
                       : grade * (std::hypot(beyond, toe) - toe) + 0.5 * grade * (climb - beyond);
    // Gullies down the fall line, 3 m wide, every `spacing` across the slope (each placed and
    // meandering its own way), deepening uphill.
    double gully = 0.0;
    const int64_t nearest = std::llround(v / spacing);
    for (int64_t k = nearest - 1; k <= nearest + 1; ++k) {
      const double centre = spacing * (k + 0.25 * HashUnit(gullies, k, 0)) +
                            2.0 * Relief(s + 7 + k, u, 0.0, 25.0, 8.0);
      gully = std::max(gully, 1.0 - std::abs(v - centre) / 1.5);
    }
    const double depth = std::min(4.0, 0.15 * climb);
    const double behind = 0.03 * std::min(u, 0.0);  // falling gently behind the station
    return slope - depth * gully + behind + 0.8 * Relief(s, x, y, 30.0, 4.0);
  });
}

// The station on a narrow crest: the ground falls away on both flanks, convex, so that beyond
// the brow (some 8-12 m out) the flanks are hidden; the crest itself undulates and descends
// gently along its length.
void Ridge(uint64_t s, std::mt19937_64& rng, Scene* scene) {
  const Frame f = RandomFrame(rng);
  const double drop = Uniform(rng, 9.0, 14.0), half_width = 25.0;
  const double asymmetry = Uniform(rng, 0.8, 1.2), grade = Uniform(rng, 0.02, 0.06);
  FillLattice(scene, [&](double x, double y) {
    const double u = f.U(x, y), v = f.V(x, y);
    const double side = v < 0.0 ? asymmetry : 1.0 / asymmetry;
    const double w = std::abs(v) / half_width;
    // Parabolic within half_width, then straight on at the slope it reached.
    const double flank = drop * side * (w < 1.0 ? w * w : 2.0 * w - 1.0);
    return -flank - grade * u + 0.6 * Relief(s, x, y, 40.0, 4.0);
  });
}

// Badlands: steep ground with 30-60 m of relief in the station's 60 m square, cut by gullies
// with narrow floors whose flanks hide them from a tripod on the interfluves.
void Badlands(uint64_t s, std::mt19937_64& rng, Scene* scene) {
  const Frame f = RandomFrame(rng);
  const double tilt = Uniform(rng, 0.25, 0.45), gully_depth = Uniform(rng, 6.0, 10.0);
  FillLattice(scene, [&](double x, double y) {
    double h = tilt * f.U(x, y) + 12.0 * Relief(s, x, y, 60.0, 6.0, 0.45);
    for (int k = 0; k < 2; ++k) {
      const double line = std::abs(Relief(s + 17 + k, x, y, 45.0 / (k + 1), 15.0 / (k + 1)));
      h -= gully_depth / (k + 1) * std::pow(std::max(0.0, 1.0 - 5.0 * line), 1.5);
    }
    return h;
  });
}

}  // namespace

const std::vector<std::string>& LandformSceneNames() {
  static const std::vector<std::string> names = {"embankment", "terraces", "foot", "ridge",
                                                 "badlands"};
  return names;
}

bool FillLandformScene(const std::string& name, uint64_t seed, std::mt19937_64& rng, Scene* scene) {
  if (name == "embankment") {
    Embankment(seed, rng, scene);
  } else if (name == "terraces") {
    Terraces(seed, rng, scene);
  } else if (name == "foot") {
    Foot(seed, rng, scene);
  } else if (name == "ridge") {
    Ridge(seed, rng, scene);
  } else if (name == "badlands") {
    Badlands(seed, rng, scene);
  } else {
    return false;
  }
  return true;
}

}  // namespace ts::sim
