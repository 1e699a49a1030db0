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
#include "core/options.h"

namespace ts {

struct HeightBlunderOptions {
  double window_m = 2.5;
  double threshold_m = 1.0;  // |z - median| above this: blunder
  int min_neighbours = 3;    // fewer points in the window: the point is kept, not judged
  int max_samples = 512;
  // A point off the median is still kept when at least this many other points of its window
  // lie within layer_tolerance_m of its height (0: off): it belongs to a second surface of
  // the window, not a blunder. A tripod's cloud of a forest has two: at the edge of a grove,
  // where canopy fills most of a window, the ground seen beneath and beside it is such a layer.
  int min_layer_points = 3;
  double layer_tolerance_m = 0.3;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("window_m", self.window_m, {"window of the median height", "m", 0.05, 50});
    v("threshold_m", self.threshold_m, {"|z - median| above this: blunder", "m", 0.001, 50});
    v("min_neighbours", self.min_neighbours,
      {"fewer points in the window: kept, not judged", "", 1, 1000});
    v("max_samples", self.max_samples,
      {"points of a window the median is taken over, at most", "", 3, 100000});
    v("min_layer_points", self.min_layer_points,
      {"a point with more others in its layer is no blunder", "", 0, 1000});
    v("layer_tolerance_m", self.layer_tolerance_m, {"height band of a layer", "m", 0.001, 10});
  }
  bool Check(std::string* why) const;
};

// One flag per point: 1 = blunder.
std::vector<uint8_t> FindHeightBlunders(const std::vector<Eigen::Vector3d>& points,
                                        const HeightBlunderOptions& options);

}  // namespace ts
