// Patches seen from below, on scenes built from planes around a viewpoint 1.5 m up: which
// small patches a tripod cannot see as terrain, and which it can.
#include "processing/cloud/underside_patches.h"

#include <gtest/gtest.h>

#include <functional>
#include <random>

namespace ts {
namespace {

const Eigen::Vector3d kPatchEye(0.0, 0.0, 1.5);

struct PatchScene {
  std::vector<Eigen::Vector3d> points;
  std::vector<int> patch;  // which surface each point is on
  // Points every 0.25 m over [x0, x1) x [y0, y1) on z(x), each moved along its line of sight
  // by range noise (how stereo errs).
  void Add(int id, double x0, double x1, double y0, double y1,
           const std::function<double(double)>& z, double range_sigma_m = 0.0) {
    std::normal_distribution<double> noise(0.0, range_sigma_m);
    for (double x = x0; x < x1 - 1e-9; x += 0.25)
      for (double y = y0; y < y1 - 1e-9; y += 0.25) {
        const Eigen::Vector3d p(x, y, z(x));
        const Eigen::Vector3d ray = (p - kPatchEye).normalized();
        points.push_back(p + (range_sigma_m > 0.0 ? noise(rng) : 0.0) * ray);
        patch.push_back(id);
      }
  }
  std::mt19937 rng{3};
};

TEST(UndersidePatches, FlagsSmallPatchesSeenFromBelowOnly) {
  PatchScene s;
  s.Add(0, 5, 20, -10, 10, [](double) { return 0.0; });  // the ground around the station
  // Small (4 m2), isolated patches 30 m out:
  s.Add(1, 30, 32, 0, 2, [](double) { return 4.5; });  // a ceiling 3 m above the viewpoint
  s.Add(2, 30, 32, 6, 8, [](double) { return 0.0; });  // level ground below it
  // Below the viewpoint but falling away faster than the line of sight (a canopy's underside
  // seen through a gap, as behind the simulated groves).
  s.Add(3, 30, 32, -8, -6, [](double x) { return -1.0 - 0.4 * (x - 30.0); });
  // Above the viewpoint, but rising towards it: a hillside facing the station.
  s.Add(4, 30, 32, 12, 14, [](double x) { return 3.0 + 0.3 * (x - 30.0); });
  // A large surface seen from below: the ground the DEM is made of is never flagged.
  s.Add(5, 40, 60, -10, 10, [](double) { return 3.0; });
  const std::vector<uint8_t> ground(s.points.size(), 1);
  const UndersidePatches found = FindUndersidePatches(s.points, ground, kPatchEye);
  ASSERT_EQ(found.underside.size(), s.points.size());
  for (size_t i = 0; i < s.points.size(); ++i)
    EXPECT_EQ(found.underside[i], s.patch[i] == 1 || s.patch[i] == 3) << "surface " << s.patch[i];
  EXPECT_EQ(found.small_patches, 4);
  EXPECT_EQ(found.underside_patches, 2);
}

TEST(UndersidePatches, RangeNoiseDoesNotMakeGroundAnUnderside) {
  // Range noise moves points along their lines of sight, which draws a patch's fitted slope
  // towards the line of sight's: level ground 30 m out (sight slope -0.05) stays terrain even
  // with 0.3 m of noise; the ceiling stays a ceiling.
  PatchScene s;
  s.Add(0, 5, 20, -10, 10, [](double) { return 0.0; });
  s.Add(
      1, 30, 32, 6, 8, [](double) { return 0.0; }, 0.3);
  s.Add(
      2, 30, 32, 0, 2, [](double) { return 4.5; }, 0.3);
  const UndersidePatches found =
      FindUndersidePatches(s.points, std::vector<uint8_t>(s.points.size(), 1), kPatchEye);
  for (size_t i = 0; i < s.points.size(); ++i)
    EXPECT_EQ(found.underside[i], s.patch[i] == 2) << "surface " << s.patch[i];
}

TEST(UndersidePatches, LooksOnlyAtGroundAndNeedsEnoughPoints) {
  PatchScene s;
  s.Add(0, 5, 20, -10, 10, [](double) { return 0.0; });
  s.Add(1, 30, 32, 0, 2, [](double) { return 4.5; });
  std::vector<uint8_t> ground(s.points.size(), 1);
  // The ceiling's points are not ground: nothing to flag.
  for (size_t i = 0; i < s.points.size(); ++i) ground[i] = s.patch[i] == 0;
  UndersidePatches found = FindUndersidePatches(s.points, ground, kPatchEye);
  EXPECT_EQ(found.underside_patches, 0);
  // Ground, but fewer points than a plane needs by the options: kept.
  UndersidePatchOptions o;
  o.min_points = 100;  // the ceiling has 64
  found = FindUndersidePatches(s.points, std::vector<uint8_t>(s.points.size(), 1), kPatchEye, o);
  EXPECT_EQ(found.small_patches, 1);
  EXPECT_EQ(found.underside_patches, 0);
}

TEST(UndersidePatches, FlagsSmallPatchesAmongObjectsWhicheverWayTheyFace) {
  PatchScene s;
  s.Add(0, 5, 20, -10, 10, [](double) { return 0.0; });  // the ground around the station
  // Three small level patches 30 m out, seen from above like ground (64 points each):
  s.Add(1, 30, 32, 6, 8, [](double) { return 0.0; });    // amid canopy
  s.Add(2, 30, 32, -8, -6, [](double) { return 0.0; });  // alone
  s.Add(3, 30, 32, 14, 16, [](double) { return 0.0; });  // a bush beside it, a few points
  // Canopy 2 m up all around patch 1 (192 points) and a strip beside patch 3 (32 points).
  s.Add(4, 29, 33, 5, 6, [](double) { return 2.0; });
  s.Add(4, 29, 33, 8, 9, [](double) { return 2.0; });
  s.Add(4, 29, 30, 6, 8, [](double) { return 2.0; });
  s.Add(4, 32, 33, 6, 8, [](double) { return 2.0; });
  s.Add(5, 32, 33, 14, 16, [](double) { return 0.8; });
  std::vector<uint8_t> ground(s.points.size());
  for (size_t i = 0; i < s.points.size(); ++i) ground[i] = s.patch[i] <= 3;
  const UndersidePatches found = FindUndersidePatches(s.points, ground, kPatchEye);
  for (size_t i = 0; i < s.points.size(); ++i)
    EXPECT_EQ(found.underside[i], s.patch[i] == 1) << "surface " << s.patch[i];
  EXPECT_EQ(found.among_objects, 1);
  EXPECT_EQ(found.underside_patches, 0);  // none is seen from below
  // Switched off, or asking for more canopy than there is: kept.
  UndersidePatchOptions off;
  off.object_ratio = 0.0;
  EXPECT_EQ(FindUndersidePatches(s.points, ground, kPatchEye, off).among_objects, 0);
  UndersidePatchOptions more;
  more.object_ratio = 4.0;  // patch 1 has 3 canopy points per ground point
  EXPECT_EQ(FindUndersidePatches(s.points, ground, kPatchEye, more).among_objects, 0);
}

TEST(UndersidePatches, RejectsBadInput) {
  UndersidePatchOptions o;
  o.min_points = 2;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("min_points"), std::string::npos);
  EXPECT_THROW(FindUndersidePatches({}, {}, kPatchEye, o), std::invalid_argument);
  UndersidePatchOptions ratio;
  ratio.object_ratio = -1.0;
  EXPECT_FALSE(ratio.Check(&why));
  EXPECT_NE(why.find("object_ratio"), std::string::npos);
  UndersidePatchOptions ring;
  ring.object_ring_cells = -1;
  EXPECT_FALSE(ring.Check(&why));
  EXPECT_NE(why.find("object_ring_cells"), std::string::npos);
  EXPECT_THROW(FindUndersidePatches({{0, 0, 0}}, {}, kPatchEye), std::invalid_argument);
  EXPECT_TRUE(FindUndersidePatches({}, {}, kPatchEye).underside.empty());
}

}  // namespace
}  // namespace ts
