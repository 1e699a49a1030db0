#pragma once
// The squares between a detected grid of chessboard corners, as the image shows them: whether
// the grid is the board's own lattice, and which of its corners it is when the board carries
// circle markers (chessboard.h).
//
// OpenCV's sector-based detector with CALIB_CB_LARGER returns the part of a board in view, but
// its own marker search (CALIB_CB_MARKER, OpenCV 4.6) refuses boards whose markers are plainly
// in view (on a rendered session of boards held at 1-2.5 m: half the views), so the markers
// are found here, from the squares' colours.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "processing/calibration/chessboard.h"

namespace ts {

// Corners found as a grid, row-major.
struct CornerGrid {
  int columns = 0, rows = 0;
  std::vector<Eigen::Vector2d> corners;
  const Eigen::Vector2d& at(int c, int r) const { return corners[r * columns + c]; }
};

// Per square of the grid ((columns - 1) x (rows - 1), row-major): its level away from its
// edges and from its centre, the spread of that level, and its level at the centre, where a
// circle marker would be.
struct GridSquares {
  int columns = 0, rows = 0;
  std::vector<double> level, spread, centre;
  double dark = 0.0, light = 0.0;  // the darkest and the lightest square's level
  double Contrast() const { return light - dark; }
  double Middle() const { return 0.5 * (light + dark); }
};

GridSquares SampleSquares(const cv::Mat& grey, const CornerGrid& grid);

// Whether the grid is the board's lattice: each square of one colour, dark and light
// alternating. Free to choose the grid's extent, the detector can return, on a strongly
// tilted board, a lattice of every other corner turned by 45 degrees, whose cells hold parts of
// four squares. A true lattice passes in every square but where something covers the board.
bool IsBoardLattice(const GridSquares& squares);

// Each grid corner's index in ChessboardCorners(board), from the three circle markers: the
// light square with a dark circle is the origin square, the two dark squares with light
// circles beside it give the board's x and y (x is the one from which y turns clockwise in the
// image: a board seen from its front is never mirrored). None when the markers are not all in
// view, or the grid, so placed, runs off the board.
std::optional<std::vector<int>> NumberByCircleMarkers(const CornerGrid& grid,
                                                      const GridSquares& squares,
                                                      const ChessboardOptions& board);

}  // namespace ts
