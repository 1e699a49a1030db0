#pragma once
// Median-height blunder filter (seed 003, sec. 3.3): a point whose height differs from the
// median height of the points in a window centred on it by more than a threshold is a
// blunder. The window is a square of window_m on a side, centred on the point's cell of a
// grid of window_m / 5 (so the window is that cell and two cells around it: points of one
// cell share a median, which makes the filter linear in the number of points). Medians of
// crowded windows are taken from an even subsample of at most max_samples points.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace ts {

struct HeightBlunderOptions {
  double window_m = 2.5;
  double threshold_m = 1.0;  // |z - median| above this: blunder
  int min_neighbours = 3;    // fewer points in the window: the point is kept, not judged
  int max_samples = 512;
  bool Check(std::string* why) const;
};

// One flag per point: 1 = blunder.
std::vector<uint8_t> FindHeightBlunders(const std::vector<Eigen::Vector3d>& points,
                                        const HeightBlunderOptions& options);

}  // namespace ts
