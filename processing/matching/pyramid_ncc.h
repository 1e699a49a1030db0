#pragma once
// Approximate disparities for every pixel by normalised cross-correlation on an image
// pyramid (seed 003 sec. 4: "epipolar search with NCC on a pyramid"). Rectified images:
// left (x, y) shows what right (x - d, y) shows.
//   - At the coarsest level the whole disparity range is searched for every pixel (a cost
//     volume of box-filtered NCC, winner takes all).
//   - Each finer level searches only +-refine_radius_px around twice the (bilinearly
//     upsampled) coarser disparity. The window of a pixel is compared with the right image
//     under each neighbour's own hypothesis, so on a slanted surface (near ground) the
//     window follows the slant instead of assuming a constant disparity.
// Windows at the top and bottom rows and the last columns take the border pixels again
// (replicated), so that they have approximations too: a top-level window reaches 3 x 16 px
// at full resolution, and the top rows of a view are the far ground.
// The maps are approximations for least-squares matching, which decides what is accepted.
#include <opencv2/core.hpp>
#include <string>

#include "core/options.h"

namespace ts {

struct PyramidNccOptions {
  int half_window_px = 3;       // NCC window (2h+1)^2 at every level
  int refine_radius_px = 2;     // search +- this around the coarser level's estimate
  int coarsest_search_px = 40;  // levels are added until the range at the top spans <= this
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("half_window_px", self.half_window_px, {"NCC half window at every level", "px", 1, 50});
    v("refine_radius_px", self.refine_radius_px,
      {"search around the coarser level's estimate", "px", 1, 50});
    v("coarsest_search_px", self.coarsest_search_px,
      {"levels are added until the top's range spans this", "px", 4, 100000});
  }
  bool Check(std::string* why) const;
};

struct DisparityMap {
  cv::Mat disparity;  // CV_16SC1 at `level`, in pixels of that level; -1 = none
  cv::Mat score;      // CV_32FC1, NCC of the winner
  int level = 0;      // one pixel of the maps is 2^level pixels of the input
};

// left, right: CV_32FC1 of one size; 0 <= d_min < d_max (input pixels). The maps stop at
// finest_level (0 = full resolution).
DisparityMap MatchPyramid(const cv::Mat& left, const cv::Mat& right, int d_min, int d_max,
                          int finest_level, const PyramidNccOptions& options);

// The best disparity for the window centred at (u, v) of `from`, searching `to` at
// u - sign * d for d in [lo, hi] (sign +1: from = left; -1: from = right). -1 if no
// candidate fits in the image; score receives the NCC.
int BestDisparityAt(const cv::Mat& from, const cv::Mat& to, int u, int v, int lo, int hi,
                    int half_window_px, int sign, double* score);

}  // namespace ts
