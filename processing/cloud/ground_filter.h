#pragma once
// Ground filter: separates bare earth from trees, bushes and other above-ground objects in a
// point cloud. The simple morphological filter (SMRF, Pingel, Vosselman & Ogundipe 2013):
//  1. the lowest point of every cell of a grid is a first, too-low surface; empty cells
//     (occlusion shadows behind objects, density falling with range) are filled (FillHoles);
//  2. progressive morphological opening with disks of radius 1 .. max_window_m: a cell that
//     the opening lowers by more than slope x radius belongs to an object (with
//     slope_from_terrain, by more than the terrain's own regional gradient allows, see below);
//  3. the surface without those cells, filled again, is the provisional ground;
//  4. a point is ground when it lies within elevation_threshold_m + elevation_scaler x (local
//     slope of the provisional ground) of it (the slope term allows for steep cells).
// It needs no ordering or scan geometry, so it serves terrestrial clouds as well as airborne.
// A tripod's cloud holds only the face of a grove (the ground behind it is hidden): a grove
// deeper than the largest opening reaches from the ground seen in front stays ground.
// Objects already known (e.g. canopy found along the lines of sight) say where ground is
// hidden: the filled empty cells near them fall away from the cells seen, so that the low
// rim of a grove (bush tops, the bottom of a canopy) stands above what lies behind it and
// the opening takes it, where the fill would otherwise carry it on as a plateau.
//
// Steep ground: an opening of radius r lowers a surface whose gradient nowhere exceeds G by at
// most G r (the erosion takes the lowest point within r, at most G r down; the dilation lifts
// it back at least as far). A fixed slope therefore cuts the ribs and crests of ground steeper
// than it, as objects: the spurs between a badland's gullies, the convex foot of a 40 degree
// slope. With slope_from_terrain the allowance at a cell is the terrain's regional gradient
// where that is steeper than `slope`: the gradient of the largest opening's surface (objects
// narrower than it gone), averaged over the opening's width so that the edge of a grove wider
// than the opening does not raise its own allowance. A tree on such ground still goes: its
// lowest points stand metres above the ground within a crown's radius. Off by default: on the
// airborne ISPRS samples it keeps buildings on steep hillsides (samp11's type II error 6.9 ->
// 18.4 %, the mean total 3.4 -> 4.0 %); a tripod's objects are trees and bushes.
#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>
#include "core/options.h"

namespace ts {

struct GroundFilterOptions {
  double cell_m = 1.0;
  double slope = 0.15;         // steepest terrain slope to keep (rise over run)
  double max_window_m = 18.0;  // radius of the largest opening: wider than any object
  double elevation_threshold_m = 0.5;
  double elevation_scaler = 1.25;
  // Empty cells within this of a cell holding a known object point (0: off) are filled
  // falling away from the nearest cell seen by this much (rise over run): ground under an
  // object lies below the object's lowest visible part.
  double object_shadow_m = 4.0;
  double object_shadow_fall = 0.3;
  bool slope_from_terrain = false;  // the slope allowance rises to the terrain's (above)
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("cell_m", self.cell_m, {"grid cell", "m", 0.05, 20});
    v("slope", self.slope, {"steepest terrain slope kept (rise over run)", "", 0, 10});
    v("max_window_m", self.max_window_m,
      {"largest opening radius, wider than any object", "m", 0.05, 100});
    v("elevation_threshold_m", self.elevation_threshold_m,
      {"height above the ground surface still ground", "m", 0.001, 20});
    v("elevation_scaler", self.elevation_scaler,
      {"threshold growth with the local slope", "", 0, 10});
    v("object_shadow_m", self.object_shadow_m,
      {"hidden cells this near a known object are filled falling away", "m", 0, 50});
    v("object_shadow_fall", self.object_shadow_fall,
      {"how fast they fall away (rise over run)", "", 0, 10});
    v("slope_from_terrain", self.slope_from_terrain,
      {"slope allowance rises to the terrain's regional gradient"});
  }
  bool Check(std::string* why) const;
  // For a tripod's cloud: a tighter band around the ground and a smaller slope allowance than
  // the airborne defaults above (the near ground is dense and precise; trees stand close); the
  // band grows with the local slope by a cell's span.
  static GroundFilterOptions ForTripod();
};

struct GroundFilterResult {
  std::vector<uint8_t> ground;  // one flag per input point, 1 = ground
  // The provisional ground surface on the filter's grid (row 0 at min_y, CV_32FC1).
  cv::Mat surface;
  double min_x_m = 0.0, min_y_m = 0.0, cell_m = 1.0;
};

// known_objects: points known not to be ground (not classified, only used as above).
GroundFilterResult FilterGround(const std::vector<Eigen::Vector3d>& points,
                                const GroundFilterOptions& options,
                                const std::vector<Eigen::Vector3d>& known_objects = {});

}  // namespace ts
