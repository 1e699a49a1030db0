#pragma once
// The Förstner interest operator (Förstner & Gülch 1987), as seed 003 uses it to place dense
// points for matching. From the structure tensor N = sum over a window of [gx^2 gxgy; gxgy
// gy^2]: weight w = det N / trace N (how precisely a point can be located) and roundness
// q = 4 det N / trace^2 N (1 for a corner or blob, 0 for a straight edge).
//
// Points are spread over the image on a grid: at most one per cell (its strongest local
// maximum of w, or in dense use its strongest pixel) and none closer than half a cell to a
// stronger one, so texture everywhere is sampled, not only its strongest clumps. Each
// point is located to sub-pixel precision by Förstner's estimate: the point nearest, in the
// least-squares sense, to all the gradient lines of its window.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/options.h"

namespace ts {

struct ForstnerOptions {
  int half_window_px = 2;          // structure-tensor window (2h+1)^2 for w and q
  int locate_half_window_px = 4;   // window of the sub-pixel estimate: wider, so the edges
                                   // dominate the blurred corner's own pixels
  double min_roundness = 0.5;      // q threshold: rejects edges
  double min_weight_factor = 1.0;  // w threshold, times the image's median w
  int cell_px = 8;                 // grid cell: at most one point per cell (density)
  // true: a cell's point must be a local maximum of w (the classic operator: corners only);
  // false: every cell with enough texture gives its strongest pixel (dense matching).
  bool local_maxima_only = true;
  bool subpixel = true;  // false: the pixel itself (e.g. for a matcher whose windows sit on pixels)
  int border_px = 8;     // no points this close to the image border
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("half_window_px", self.half_window_px, {"structure-tensor half window", "px", 1, 10});
    v("locate_half_window_px", self.locate_half_window_px,
      {"half window of the sub-pixel estimate", "px", 1, 50});
    v("min_roundness", self.min_roundness, {"q threshold: rejects edges", "", 0, 1});
    v("min_weight_factor", self.min_weight_factor,
      {"w threshold, times the image's median w", "", 1e-6, 1e6});
    v("cell_px", self.cell_px, {"at most one point per grid cell", "px", 2, 10000});
    v("local_maxima_only", self.local_maxima_only,
      {"a cell's point must be a local maximum of w (off: dense)"});
    v("subpixel", self.subpixel, {"sub-pixel position (off: the pixel itself)"});
    v("border_px", self.border_px, {"no points this close to the border", "px", 2, 10000});
  }
  bool Check(std::string* why) const;
};

struct InterestPoint {
  Eigen::Vector2d position_px{0, 0};  // sub-pixel
  double weight = 0.0;
  double roundness = 0.0;
};

// image: CV_8UC1, CV_16UC1 or CV_32FC1.
std::vector<InterestPoint> DetectForstner(const cv::Mat& image, const ForstnerOptions& options);

}  // namespace ts
