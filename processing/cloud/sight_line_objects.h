#pragma once
// Object points found along the lines of sight of the views that saw them. Seen from one
// viewpoint, a terrain that is a height field gets farther away, along any azimuth, the
// higher the ray looks, and rises gently with that distance. Two kinds of point break this
// and cannot be terrain, whatever a ground filter's surface says:
//  - floating: a ray below the point's meets something farther away, so it passed beneath the
//    point (a canopy with the ground seen past the trunks, a branch, anything overhanging);
//  - on a face: the rays a little below the point's meet surfaces at about its distance but
//    lower, so the point sits on a face steeper than any terrain (a trunk, a canopy front, a
//    wall; also the riser of a terrain step, which a 1 m DEM does not need).
// A tripod's cloud needs this behind groves, where no ground is seen in front of the canopy
// and the morphological filter has nothing lower to compare it with.
//
// Per viewpoint (the pair's left camera), points are binned by azimuth and sorted by
// elevation. Floating: bins of azimuth_bin_deg swept from the lowest ray up, keeping the
// farthest horizontal distances seen so far (less their uncertainty); a point floats when
// min_witnesses of them lie beyond it by more than min_gap_m and sigma_factor times its own
// horizontal sigma. Faces: bins of face_bin_deg; the medians of the height and distance
// differences to the rays face_min_below_deg .. face_max_below_deg lower (at least
// min_face_rays of them) must not rise steeper than max_terrain_inclination_deg.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/cloud/point_cloud.h"

namespace ts {

struct SightLineOptions {
  double azimuth_bin_deg = 0.05;  // 3.5 cm at 40 m
  double min_gap_m = 0.5;
  double sigma_factor = 3.0;
  int min_witnesses = 2;  // a single far blunder below proves nothing
  // Faces: a canopy's or a trunk's side, seen as points above lines of sight that passed
  // beneath them at a steeper angle than terrain can have.
  double face_bin_deg = 1.0;
  double face_min_below_deg = 0.3;
  double face_max_below_deg = 2.0;
  int min_face_rays = 3;
  double max_terrain_inclination_deg = 60.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("azimuth_bin_deg", self.azimuth_bin_deg,
      {"azimuth bin of the lines of sight", "deg", 0.001, 5});
    v("min_gap_m", self.min_gap_m,
      {"a point this far above a line of sight that passed beneath it floats", "m", 0, 50});
    v("sigma_factor", self.sigma_factor, {"the gap in the points' sigmas, at least", "", 0, 100});
    v("min_witnesses", self.min_witnesses,
      {"lines of sight needed to call a point floating", "", 1, 8});
    v("face_bin_deg", self.face_bin_deg, {"azimuth bin of the face test", "deg", 0.001, 5});
    v("face_min_below_deg", self.face_min_below_deg,
      {"a face's points seen this far below the line, at least", "deg", 0, 90});
    v("face_max_below_deg", self.face_max_below_deg, {"and at most", "deg", 0, 90});
    v("min_face_rays", self.min_face_rays, {"lines of sight that make a face", "", 1, 1000});
    v("max_terrain_inclination_deg", self.max_terrain_inclination_deg,
      {"faces steeper than terrain can be", "deg", 0.1, 89.9});
  }
  bool Check(std::string* why) const;
};

struct SightLineObjects {
  std::vector<uint8_t> floating, on_face;  // one flag per point, 1 = object
  int floating_count = 0, face_count = 0;
};

// viewpoints: the projection centre of each pair's left camera in L, by CloudPoint::pair.
// Points of pairs without a viewpoint are never flagged.
SightLineObjects FindSightLineObjects(const PointCloud& cloud,
                                      const std::map<int, Eigen::Vector3d>& viewpoints,
                                      const SightLineOptions& options = {});

}  // namespace ts
