// The built-in scenes. Each is a height function of (x, y) in metres plus, for `forest`,
// trees and bushes; all randomness comes from the seed. The landforms of issue 22 are in
// scene_landforms.cc.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "sim/noise.h"
#include "sim/scene.h"
#include "sim/scene_landforms.h"

namespace ts::sim {
namespace {

Lighting RandomSun(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> azimuth(0.0, 2.0 * std::numbers::pi),
      elevation(35.0, 60.0);
  const double az = azimuth(rng), el = elevation(rng) * std::numbers::pi / 180.0;
  Lighting l;
  l.to_sun = SunDirection(az, el);
  return l;
}

struct Rock {
  double x, y, radius, height;
};

std::vector<Rock> RandomRocks(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> pos(-45.0, 45.0), radius(0.3, 1.2), height(0.2, 0.8);
  std::vector<Rock> rocks;
  while (static_cast<int>(rocks.size()) < count) {
    Rock r{pos(rng), pos(rng), radius(rng), height(rng)};
    if (std::hypot(r.x, r.y) > r.radius + 2.5) rocks.push_back(r);  // keep the tripod clear
  }
  return rocks;
}

SceneObject RandomTree(std::mt19937_64& rng, double x, double y, double ground_z) {
  std::uniform_real_distribution<double> canopy(1.5, 3.0), trunk(1.5, 3.5), tr(0.1, 0.25),
      squash(0.85, 1.15);
  SceneObject t;
  t.kind = ObjectKind::kTree;
  t.ground = {x, y, ground_z};
  const double r = canopy(rng);
  t.canopy_radii_m = {r * squash(rng), r * squash(rng), r * squash(rng)};
  t.trunk_height_m = trunk(rng) + 0.5 * t.canopy_radii_m.z();
  t.trunk_radius_m = tr(rng);
  t.canopy_centre = {x, y, ground_z + t.trunk_height_m};
  return t;
}

SceneObject RandomBush(std::mt19937_64& rng, double x, double y, double ground_z) {
  std::uniform_real_distribution<double> radius(0.4, 1.2), height(0.3, 0.8);
  SceneObject b;
  b.kind = ObjectKind::kBush;
  b.ground = {x, y, ground_z};
  const double r = radius(rng);
  b.canopy_radii_m = {r, r * 0.9, height(rng)};
  b.canopy_centre = {x, y, ground_z + 0.6 * b.canopy_radii_m.z()};
  return b;
}

// Trees and bushes in groves until `cover` of the scene area lies under a canopy, leaving the
// station and its first metres clear.
void PlantGroves(Scene* scene, std::mt19937_64& rng, double cover) {
  const int cells = static_cast<int>(2 * scene->half_extent_m);
  std::vector<char> covered(static_cast<size_t>(cells) * cells, 0);
  int covered_count = 0;
  auto mark = [&](const SceneObject& o) {
    const double r = std::max(o.canopy_radii_m.x(), o.canopy_radii_m.y());
    for (int cy = 0; cy < cells; ++cy) {
      const double y = -scene->half_extent_m + cy + 0.5;
      if (std::abs(y - o.canopy_centre.y()) > r) continue;
      for (int cx = 0; cx < cells; ++cx) {
        const double x = -scene->half_extent_m + cx + 0.5;
        char& c = covered[static_cast<size_t>(cy) * cells + cx];
        if (!c && o.Covers(x, y)) c = 1, ++covered_count;
      }
    }
  };
  std::uniform_real_distribution<double> pos(-55.0, 55.0), unit(0.0, 1.0);
  std::vector<Eigen::Vector2d> groves;
  while (groves.size() < 14) {
    const Eigen::Vector2d g(pos(rng), pos(rng));
    if (g.norm() > 12.0) groves.push_back(g);
  }
  std::normal_distribution<double> scatter(0.0, 7.0);
  const double target = cover * cells * cells;
  for (size_t k = 0; covered_count < target && k < 20000; ++k) {
    const Eigen::Vector2d& g = groves[k % groves.size()];
    const double x = g.x() + scatter(rng), y = g.y() + scatter(rng);
    if (std::hypot(x, y) < 6.0 || std::abs(x) > 58.0 || std::abs(y) > 58.0) continue;
    const double z = scene->TerrainHeight(x, y);
    const SceneObject o = unit(rng) < 0.6 ? RandomTree(rng, x, y, z) : RandomBush(rng, x, y, z);
    scene->objects.push_back(o);
    mark(o);
  }
}

}  // namespace

const std::vector<std::string>& BuiltinSceneNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = {"flat", "hills", "slope", "rough", "forest"};
    for (const std::string& landform : LandformSceneNames()) n.push_back(landform);
    return n;
  }();
  return names;
}

Result<Scene> MakeBuiltinScene(const std::string& name, uint64_t seed) {
  Scene scene;
  scene.name = name;
  scene.seed = seed;
  std::mt19937_64 rng(Hash(seed, 0x5ce7e, 0));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double direction = 2.0 * std::numbers::pi * unit(rng);
  const double cd = std::cos(direction), sd = std::sin(direction);
  const uint64_t s = Hash(seed, 1, 2);
  if (name == "flat") {
    // A gentle grade (0.4-1 %) and long, low undulations: slopes stay below 2 %.
    const double grade = 0.004 + 0.006 * unit(rng);
    FillLattice(&scene, [&](double x, double y) {
      return grade * (cd * x + sd * y) + 0.25 * Relief(s, x, y, 60.0, 15.0);
    });
  } else if (name == "hills") {
    FillLattice(&scene, [&](double x, double y) { return 9.0 * Relief(s, x, y, 80.0, 5.0); });
  } else if (name == "slope") {
    const double slope_deg = 15.0 + 10.0 * unit(rng);
    const double grade = std::tan(slope_deg * std::numbers::pi / 180.0);
    FillLattice(&scene, [&](double x, double y) {
      return grade * (cd * x + sd * y) + 2.0 * Relief(s, x, y, 40.0, 5.0);
    });
  } else if (name == "rough") {
    const std::vector<Rock> rocks = RandomRocks(rng, 70);
    const double step_dir = 2.0 * std::numbers::pi * unit(rng);
    FillLattice(&scene, [&](double x, double y) {
      double h = 6.0 * Relief(s, x, y, 60.0, 8.0);
      // Gullies along the zero lines of a slow noise field.
      const double g = std::min(1.0, std::abs(Relief(s + 7, x, y, 50.0, 25.0)) * 8.0);
      h -= 1.5 * (1.0 - g) * (1.0 - g);
      // Steps: a 0.4 m riser every 7 m across the slope.
      const double u = (std::cos(step_dir) * x + std::sin(step_dir) * y) / 7.0;
      h += 0.4 * (std::floor(u) + Smoothstep((u - std::floor(u) - 0.9) / 0.1));
      for (const Rock& r : rocks) {
        const double d2 = ((x - r.x) * (x - r.x) + (y - r.y) * (y - r.y)) / (r.radius * r.radius);
        if (d2 < 1.0) h += r.height * std::sqrt(1.0 - d2);
      }
      return h;
    });
  } else if (name == "forest") {
    FillLattice(&scene, [&](double x, double y) { return 6.0 * Relief(s, x, y, 80.0, 5.0); });
    PlantGroves(&scene, rng, 0.22 + 0.1 * unit(rng));
  } else if (!FillLandformScene(name, s, rng, &scene)) {
    std::string known;
    for (const std::string& n : BuiltinSceneNames()) known += (known.empty() ? "" : ", ") + n;
    return Error{"unknown scene '" + name + "' (built-in scenes: " + known + ")"};
  }
  scene.lighting = RandomSun(rng);
  return scene;
}

}  // namespace ts::sim
