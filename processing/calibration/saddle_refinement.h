#pragma once
// Sub-pixel X-junctions: the inner corners of chessboards and ChArUco boards. A corner is the
// point where the image's gradients in a window about it are orthogonal to the lines from it
// (each pixel on one of the junction's edges sees its gradient across the edge, and the edge
// runs through the corner), solved by iterated least squares as OpenCV's cornerSubPix does.
// Two things cornerSubPix does not do:
//  - The image is smoothed first. An X-junction is symmetric about its centre, and a symmetric
//    smoothing keeps that centre where it is, while it spreads a sharp, aliased edge over pixels
//    enough for its gradient to be sampled (on rendered boards the corners' error halves).
//  - Pixels can be left out (a ChArUco marker beside the corner): the window is not bounded by
//    the nearest thing that is not the corner's edges, only its pixels are, so it can reach
//    along the edges as far as the board allows.
#include <Eigen/Core>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

namespace ts {

struct SaddleRefinementOptions {
  double smoothing_px = 1.0;  // sigma of the Gaussian the image is smoothed with
  int max_iterations = 30;
  double tolerance_px = 1e-3;  // a step shorter than this ends the iterations
};

// Pixels (image coordinates) a corner's refinement may use; true for every pixel when empty.
using SaddlePixelTest = std::function<bool(size_t corner, const Eigen::Vector2d& pixel)>;

// Refines `corners` in place. `half_window` (px) per corner: the window reaches that far from
// the corner in x and y, and must hold no other junction. A corner whose window has too
// little gradient to fix it, or that moves off the image, is left where it was and false is
// returned for it in `refined`.
void RefineSaddles(const cv::Mat& grey, const std::vector<double>& half_window,
                   const SaddlePixelTest& usable, const SaddleRefinementOptions& options,
                   std::vector<Eigen::Vector2d>* corners, std::vector<bool>* refined);

}  // namespace ts
