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
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace ts {

struct UndersidePatchOptions {
  double cell_m = 1.0;
  int gap_cells = 0;
  double max_area_m2 = 15.0;
  int min_points = 10;
  double slope_margin = 0.05;  // rise over run
  bool Check(std::string* why) const;
};

struct UndersidePatches {
  std::vector<uint8_t> underside;  // one flag per point, 1 = in a patch seen from below
  int small_patches = 0, underside_patches = 0;
};

// ground: one flag per point (1 = ground); only ground points are looked at. viewpoint: where
// the points were seen from (the station, in the points' frame).
UndersidePatches FindUndersidePatches(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<uint8_t>& ground,
                                      const Eigen::Vector3d& viewpoint,
                                      const UndersidePatchOptions& options = {});

}  // namespace ts
