// What changes at a site between two surveys: the ground (a subsidence bowl) and the light.
#include <cmath>
#include <numbers>

#include "sim/scene.h"

namespace ts::sim {

double Subsidence::LoweringAt(double x_m, double y_m) const {
  const double r = std::hypot(x_m - centre_m.x(), y_m - centre_m.y());
  if (r >= radius_m) return 0.0;
  return depth_m * 0.5 * (1.0 + std::cos(std::numbers::pi * r / radius_m));
}

double Subsidence::Volume() const {
  constexpr double kPi = std::numbers::pi;
  return (0.5 - 2.0 / (kPi * kPi)) * kPi * depth_m * radius_m * radius_m;
}

Status ApplySubsidence(Scene* scene, const Subsidence& bowl) {
  if (!(bowl.radius_m > 0.0 && bowl.radius_m <= 50.0))
    return Error{"subsidence: radius must be in (0, 50] m"};
  if (!(bowl.depth_m > 0.0 && bowl.depth_m <= 10.0))
    return Error{"subsidence: depth must be in (0, 10] m"};
  constexpr double kTripodClearance_m = 1.0;
  if (bowl.centre_m.norm() < bowl.radius_m + kTripodClearance_m)
    return Error{
        "subsidence: the bowl must stay 1 m clear of the station mark (the station frame is "
        "tied to it); move its centre or shrink its radius"};
  for (int iy = 0; iy < scene->n; ++iy)
    for (int ix = 0; ix < scene->n; ++ix)
      scene->lattice(ix, iy) -=
          static_cast<float>(bowl.LoweringAt(scene->LatticeX(ix), scene->LatticeX(iy)));
  for (SceneObject& o : scene->objects) {
    const double dz = bowl.LoweringAt(o.ground.x(), o.ground.y());
    o.ground.z() -= dz;
    o.canopy_centre.z() -= dz;
  }
  scene->subsidence.push_back(bowl);
  return {};
}

Status SetSun(Scene* scene, double azimuth_deg, double elevation_deg) {
  if (!(elevation_deg >= 5.0 && elevation_deg <= 90.0))
    return Error{"sun: elevation must be in [5, 90] degrees"};
  if (!std::isfinite(azimuth_deg)) return Error{"sun: azimuth must be a number of degrees"};
  scene->lighting.to_sun = SunDirection(azimuth_deg * std::numbers::pi / 180.0,
                                        elevation_deg * std::numbers::pi / 180.0);
  return {};
}

}  // namespace ts::sim
