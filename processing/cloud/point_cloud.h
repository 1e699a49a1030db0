#pragma once
// The merged point cloud of a station: every point in the station frame L with its 3x3
// covariance, the pair it came from, and the quality of its match.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ts {

// The least-squares window a point was matched in.
struct MatchWindow {
  Eigen::Vector2f centre_px = Eigen::Vector2f::Zero();
  Eigen::Vector2f half_size_px = Eigen::Vector2f::Zero();  // zero: not matched in a window
};

struct CloudPoint {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();     // frame L
  Eigen::Matrix3f covariance_m2 = Eigen::Matrix3f::Zero();  // frame L
  int pair = -1;                                            // index in the capture plan
  float correlation = 0.0f;                                 // of the fitted LSM windows
  float sigma_disparity_px = 0.0f;                          // of the match
  // Where the pair's rectified left image matched it, and half its window (pixels): points of
  // one pair whose windows overlap share image noise (MatchWindow).
  MatchWindow window;
};

using PointCloud = std::vector<CloudPoint>;

}  // namespace ts
