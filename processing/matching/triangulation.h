#pragma once
// Space intersection of the matches of one rectified pair, in the normal case that
// rectification makes exact: with the left projection centre at the origin of the rectified
// frame and the right one at (B, 0, 0), a match (x, y, d) lies at
//   Z = f B / d,  X = (x - cx) B / d,  Y = (y - cy) B / d.
// This is the least-squares intersection of the two rays (intersection.h) when the
// y-parallax is zero, at a fraction of its cost. The left position is the template centre
// and defines the left ray; all uncertainty is the disparity's, so the covariance is
// J sigma_d^2 J^T with J = d(X, Y, Z)/d d, along the ray. Points are then taken into the
// station frame L by the left camera's pose.
#include <Eigen/Geometry>
#include <vector>

#include "processing/cloud/point_cloud.h"
#include "processing/matching/pair_matcher.h"
#include "processing/matching/rectification.h"

namespace ts {

// Point in the rectified left frame (m) and its covariance; false for d <= 0.
bool TriangulateRectified(const Rectification& r, const StereoMatch& match,
                          Eigen::Vector3d* point_rect, Eigen::Matrix3d* covariance_rect);

// All matches of a pair, in L. l_from_left_camera: Calibration::LFromCamera(kLeft, pan,
// tilt) with the encoder read-back of the pair.
void AppendPairPoints(const Rectification& r, const std::vector<StereoMatch>& matches,
                      const Eigen::Isometry3d& l_from_left_camera, int pair, PointCloud* cloud);

}  // namespace ts
