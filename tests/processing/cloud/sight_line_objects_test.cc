// Objects along the lines of sight, on clouds built as one viewpoint 1.5 m above the ground
// would see them: a ray every 0.02 deg of azimuth and elevation meets the first surface.
#include "processing/cloud/sight_line_objects.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

namespace ts {
namespace {

constexpr double kHeight = 1.5;  // the viewpoint above z = 0
constexpr double kDeg = M_PI / 180.0;

// A surface: the distance along a horizontal direction at which a ray of the given elevation
// first meets it, if it does within 60 m (marched in 2 cm steps).
using Surface = std::function<std::optional<double>(double elevation)>;

// Rays over azimuths 0..1 deg (every 0.02) and elevations -30..20 deg (every 0.05); each hit
// becomes a point of pair 0 with a 2 cm sigma.
PointCloud See(const Surface& surface) {
  PointCloud cloud;
  for (double az = 0.0; az < 1.0; az += 0.02)
    for (double el = -30.0; el < 20.0; el += 0.05) {
      const std::optional<double> d = surface(el * kDeg);
      if (!d) continue;
      CloudPoint p;
      p.position_m = {*d * std::cos(az * kDeg), *d * std::sin(az * kDeg),
                      kHeight + *d * std::tan(el * kDeg)};
      p.covariance_m2 = Eigen::Matrix3f::Identity() * 4e-4f;
      p.pair = 0;
      cloud.push_back(p);
    }
  return cloud;
}

// March a ray over a height field with overhanging objects given as a predicate.
Surface March(const std::function<double(double)>& terrain,
              const std::function<bool(double, double)>& solid = {}) {
  return [terrain, solid](double elevation) -> std::optional<double> {
    for (double d = 0.5; d < 60.0; d += 0.02) {
      const double z = kHeight + d * std::tan(elevation);
      if (z <= terrain(d) || (solid && solid(d, z))) return d;
      if (z > 25.0) break;
    }
    return std::nullopt;
  };
}

const std::map<int, Eigen::Vector3d> kViewpoint = {{0, Eigen::Vector3d(0, 0, kHeight)}};

int Count(const std::vector<uint8_t>& flags) {
  int n = 0;
  for (uint8_t f : flags) n += f;
  return n;
}

TEST(SightLineObjects, FlatGroundAndASteepSlopeAreTerrain) {
  for (const double slope_deg : {0.0, 35.0}) {
    const PointCloud cloud = See(
        March([&](double d) { return d < 5.0 ? 0.0 : (d - 5.0) * std::tan(slope_deg * kDeg); }));
    ASSERT_GT(cloud.size(), 5000u);
    const SightLineObjects found = FindSightLineObjects(cloud, kViewpoint);
    EXPECT_EQ(Count(found.floating), 0) << slope_deg;
    EXPECT_EQ(Count(found.on_face), 0) << slope_deg;
  }
}

TEST(SightLineObjects, AWallIsAFaceAndTheGroundBeforeAndAboveItIsNot) {
  // A 2 m wall 10 m away; the ground beyond it rises, so rays above the wall see it.
  const PointCloud cloud = See(March([](double d) {
    return d < 10.0 ? 0.0 : d < 10.2 ? 2.0 : 0.5 + 0.3 * (d - 10.2);
  }));
  const SightLineObjects found = FindSightLineObjects(cloud, kViewpoint);
  int wall = 0, wall_found = 0, ground_found = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const double d = cloud[i].position_m.head<2>().norm(), z = cloud[i].position_m.z();
    const bool on_wall = d > 9.98 && d < 10.03 && z > 0.3;
    wall += on_wall;
    wall_found += on_wall && found.on_face[i];
    ground_found += !on_wall && z < 0.01 && found.on_face[i];
  }
  ASSERT_GT(wall, 100);
  EXPECT_GT(wall_found, 0.9 * wall);
  EXPECT_EQ(ground_found, 0);
  EXPECT_EQ(found.face_count, Count(found.on_face));
}

TEST(SightLineObjects, ACanopyWithTheGroundSeenBeneathItFloats) {
  // A 1 m thick canopy from 2.5 to 3.5 m over 8..12 m; the ground beneath and beyond it is
  // seen under it.
  const PointCloud cloud =
      See(March([](double) { return 0.0; },
                [](double d, double z) { return d > 8.0 && d < 12.0 && z > 2.5 && z < 3.5; }));
  const SightLineObjects found = FindSightLineObjects(cloud, kViewpoint);
  int canopy = 0, canopy_found = 0, ground_found = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const bool is_canopy = cloud[i].position_m.z() > 2.4;
    canopy += is_canopy;
    canopy_found += is_canopy && found.floating[i];
    ground_found += !is_canopy && found.floating[i];
  }
  ASSERT_GT(canopy, 100);
  EXPECT_GT(canopy_found, 0.95 * canopy);
  EXPECT_EQ(ground_found, 0);
}

TEST(SightLineObjects, OneFarBlunderBelowProvesNothing) {
  PointCloud cloud = See(March([](double) { return 0.0; }));
  // A blunder 50 m away at the lowest ray of the first bin.
  CloudPoint blunder = cloud.front();
  blunder.position_m.head<2>() *= 50.0 / blunder.position_m.head<2>().norm();
  blunder.position_m.z() = kHeight + 50.0 * std::tan(-30.0 * kDeg);
  cloud.push_back(blunder);
  const SightLineObjects found = FindSightLineObjects(cloud, kViewpoint);
  EXPECT_EQ(Count(found.floating), 0);
  // Points of a pair without a viewpoint are never flagged: not even the ground above the
  // blunder when a single witness would do.
  SightLineOptions one_witness;
  one_witness.min_witnesses = 1;
  EXPECT_GT(Count(FindSightLineObjects(cloud, kViewpoint, one_witness).floating), 0);
  for (CloudPoint& p : cloud) p.pair = 7;
  const SightLineObjects unseen = FindSightLineObjects(cloud, kViewpoint, one_witness);
  EXPECT_EQ(Count(unseen.floating) + Count(unseen.on_face), 0);
}

TEST(SightLineObjects, BadOptionsAreRefusedByName) {
  SightLineOptions o;
  o.face_max_below_deg = 0.1;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("face_max_below_deg"), std::string::npos);
  o = {};
  o.max_terrain_inclination_deg = 90.0;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_THROW(FindSightLineObjects({}, kViewpoint, o), std::invalid_argument);
}

}  // namespace
}  // namespace ts
