#pragma once
// Does the terrain go on above the top edge of a view? The capture plan's one tilt row sees
// flat ground out past the 60 m square; on a slope the uphill ground rises out of the top of
// the image a few metres from the tripod, and the DEM ends there. The capture (and `sim
// render`) then takes one more pose higher up on that azimuth (UpperPose, capture_plan.h).
//
// Judged from the pair just taken: the approximate disparities of the matching pyramid
// (pyramid_ncc.h) down to `level` give 3D points of the top band of the view in the station
// frame L. A column of the band counts as terrain going on above when its highest point is
// within far_range_m horizontally and the surface between the band's lowest and highest
// point of that column is inclined like ground (the higher point farther away, at most
// max_inclination_deg), not a vertical front such as a tree or a wall, which a higher view
// would only see more of. Sky has no texture and gives no points. Ground rises steeper than
// one might set such a limit to: at the foot of a slope a gully's wall or a spur stands 45-60
// degrees right in front of the tripod, and a limit of 50 degrees lost the pose above it and the
// 25 m of slope it would have seen; 70 leaves fronts out still (the forest's canopy fronts:
// shares 0.13-0.19 of 0.25).
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "processing/geometry/calibration.h"
#include "processing/geometry/capture_plan.h"
#include "processing/matching/rectification.h"

namespace ts {

struct TerrainAboveOptions {
  double far_range_m = 42.5;          // ground farther than this is outside the 60 m square
  double band_fraction = 0.1;         // the top band: this share of the image height
  double max_inclination_deg = 70.0;  // steeper is a front, not terrain
  double min_share = 0.25;            // of the band's columns, to take a higher pose
  int level = 1;                      // pyramid level of the disparities (1 = half resolution)
  double min_ncc = 0.8;
  double min_depth_m = 1.5, max_depth_m = 150.0;
  bool Check(std::string* why) const;
};

struct TerrainAboveVerdict {
  bool terrain_above = false;
  double share = 0.0;  // of the band's columns that see terrain going on above
};

// left, right: the raw images of one pair (any depth, single channel) taken at `pose`;
// rectification: Rectify(calibration.rig).
TerrainAboveVerdict JudgeTerrainAboveView(const Calibration& calibration,
                                          const Rectification& rectification, const cv::Mat& left,
                                          const cv::Mat& right, const StagePose& pose,
                                          const TerrainAboveOptions& options = {});

// After the pair at `taken` (the commanded pose; `reached`: where the stage read back) was
// captured: if plan options allow upper poses and the terrain goes on above this view, the
// pose above it is appended to `plan` and true is returned. One rule for the capture and for
// `sim render`.
bool ExtendPlanUpwards(const Calibration& calibration, const Rectification& rectification,
                       const cv::Mat& left, const cv::Mat& right, const StagePose& taken,
                       const StagePose& reached, const CapturePlanOptions& plan_options,
                       std::vector<StagePose>* plan);

}  // namespace ts
