#pragma once
// The merged point cloud of a station: every point in the station frame L with its 3x3
// covariance, the pair it came from, and the quality of its match.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ts {

struct CloudPoint {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();     // frame L
  Eigen::Matrix3f covariance_m2 = Eigen::Matrix3f::Zero();  // frame L
  int pair = -1;                                            // index in the capture plan
  float correlation = 0.0f;                                 // of the fitted LSM windows
  float sigma_disparity_px = 0.0f;                          // of the match
};

using PointCloud = std::vector<CloudPoint>;

}  // namespace ts
