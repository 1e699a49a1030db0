#pragma once
// The seams of a panorama (issue 21): how well neighbouring poses agree where their views
// overlap. Each tie point (rig_tie_points.h) is a point one pair intersected, found again in a
// neighbouring pose's left image; its disagreement is the distance between where the
// neighbour sees it and where the stage kinematics put the pair's point in that image. Its
// predicted sigma: the pair's intersection covariance carried into the neighbour's image, and
// two image measurements' variance (the pair's and the neighbour's), each the rig adjustment's
// sigma of that observation (its image sigma, estimated from all tie points with the stage free
// so that an error of the stage does not enter it, scaled by the measurement's own precision),
// and the two poses' read-back angles' (the stage's encoders: the seams put the views where the
// stage says they were, 0.002 deg about where they stood, 0.065 px of a 0.1 px image sigma).
// Seams that close are within 2 of it. Tie points the adjustment rejected as mismatched are left
// out: they tell of the matching, not of the stage; so are a control field's targets.
#include <Eigen/Core>
#include <vector>

#include "processing/calibration/rig_adjustment.h"

namespace ts {

struct RigSeamTie {
  int pose = 0;                                               // the neighbour
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();            // where the neighbour sees it
  Eigen::Vector2d disagreement_px = Eigen::Vector2d::Zero();  // predicted minus seen
  double ratio = 0.0;  // the disagreement's length over its predicted RMS length
  // Where it lies, seen from the stage's centre: azimuth (clockwise from L's +Y) and elevation.
  Eigen::Vector2d azimuth_elevation_deg = Eigen::Vector2d::Zero();
};

struct RigSeams {
  std::vector<RigSeamTie> ties;
  double median_px = 0.0;
  double median_mm = 0.0;  // the same across the line of sight, at the point's distance
  // Share of the ties whose ratio is at most 2; above 0.98 for a 2D normal error.
  double within_2_sigma = 0.0;
};

// The seams with `calibration`'s stage and cameras in place of in.calibration's (each pair's
// points moved with their pair's left camera): before the adjustment with in.calibration's,
// after it with the adjustment's (RigAdjustment::Adjusted). Several stations: the seams of all
// of them, or of one (`station` >= 0).
RigSeams MeasureRigSeams(const RigAdjustmentInput& in, const Calibration& calibration,
                         const RigAdjustment& adjustment, int station = -1);

}  // namespace ts
