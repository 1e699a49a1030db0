#pragma once
// Small, isolated patches of "ground" that the station sees from below. Behind a grove a tripod
// sees no ground, only here and there the underside of a canopy through a gap; the ground
// filter has nothing lower there to compare it with, and keeps it. Terrain is the upper side
// of a height field: a viewpoint sees it only from above its tangent plane, i.e. going away
// from the viewpoint the terrain must rise faster than the line of sight does. A canopy's
// underside, seen through a gap, falls away faster than the line of sight (or rises slower):
// it is seen from below.
//
// Ground cells (cell_m squares with a ground point) are grouped into patches (8-connected,
// and cells at most gap_cells empty cells apart). A patch of less than max_area_m2 of cells
// and at least min_points points gets a plane fitted to its points (least squares); it is
// seen from below when the plane's slope away from the viewpoint, at the patch, is less than
// the line of sight's by more than slope_margin (the matching noise lies along the lines of
// sight, so it draws the fitted slope towards the line of sight's, never across it).
// Larger patches are never flagged: they are the ground the DEM is made of.
//
// A small patch among objects is canopy too, whichever way it faces. Behind a grove on ground
// falling away from the station, the lower front of a canopy stands below the cameras and is
// seen from above, like ground; the ground filter has no ground behind it to compare it with.
// Such islands, 5-15 m beyond the last ground seen, anchored kriging over hundreds of square
// metres (simulated forest, seed 3: the DEM 1-2 m high over 300 m2). So a small patch with at
// least object_ratio object points (the points not flagged ground) per ground point, in its
// cells and object_ring_cells around them, is flagged as well. Real ground seen through a gap
// in a grove looks the same and is lost with it; the DEM reaches it from the ground around.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>
#include "core/options.h"

namespace ts {

struct UndersidePatchOptions {
  double cell_m = 1.0;
  int gap_cells = 0;
  double max_area_m2 = 15.0;
  int min_points = 10;
  double slope_margin = 0.05;  // rise over run
  // A small patch with at least object_ratio object points per ground point in its cells and
  // object_ring_cells around them is canopy, whichever way it faces (0: off).
  double object_ratio = 1.0;
  int object_ring_cells = 2;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("cell_m", self.cell_m, {"grid cell of the patches", "m", 0.05, 20});
    v("gap_cells", self.gap_cells, {"empty cells a patch may bridge", "", 0, 20});
    v("max_area_m2", self.max_area_m2, {"patches larger than this are terrain", "m2", 0, 10000});
    v("min_points", self.min_points, {"patches with fewer points are left alone", "", 3, 100000});
    v("slope_margin", self.slope_margin,
      {"a patch falling away faster than the line of sight by this is an underside", "", 0, 10});
    v("object_ratio", self.object_ratio,
      {"a patch amid this many object points per own point is canopy (0: off)", "", 0, 1000});
    v("object_ring_cells", self.object_ring_cells,
      {"cells around a patch where its objects are counted", "", 0, 20});
  }
  bool Check(std::string* why) const;
};

struct UndersidePatches {
  std::vector<uint8_t> underside;  // one flag per point, 1 = in a patch seen from below
  int small_patches = 0, underside_patches = 0;
  int among_objects = 0;  // small patches flagged for the objects around them
};

// ground: one flag per point (1 = ground); only ground points are looked at. viewpoint: where
// the points were seen from (the station, in the points' frame).
UndersidePatches FindUndersidePatches(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<uint8_t>& ground,
                                      const Eigen::Vector3d& viewpoint,
                                      const UndersidePatchOptions& options = {});

}  // namespace ts
