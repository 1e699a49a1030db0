#pragma once
// ChArUco boards (OpenCV contrib aruco): a chessboard whose white squares hold ArUco markers,
// so that every corner found carries its id and a part of the board counts: a board running
// off the frame still puts corners at its edges and corners, where a plain chessboard (found
// whole or not at all) cannot. The board in the frame of the chessboard of the same inner
// corners (chessboard.h): inner corner 0 at the origin, x along the columns, y along the
// rows; its squares from -1 to `columns` squares. Markers of OpenCV's 5x5 dictionaries (the
// 50, 100, 250 and 1000 share their first codes, so a board printed from any of them is found).
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "processing/calibration/chessboard.h"
#include "processing/calibration/target_views.h"

namespace ts {

struct CharucoOptions {
  ChessboardOptions corners;  // inner corners and the square's side
  // A marker's side, in squares. Half a square (OpenCV's tutorial board) leaves a quarter of a
  // square between a corner and the markers beside it, where its refinement reaches along its
  // edges (larger markers work, their corners are found less precisely).
  double marker = 0.5;
  bool Check(std::string* why) const;
};

// "12x9" squares -> 11 x 8 inner corners; false if the text is not SQUARESxSQUARES.
bool ParseCharucoSize(const std::string& text, CharucoOptions* options);

// The board as OpenCV draws it, `pixels_per_square` to a square, its squares only (no margin):
// (columns + 1) x (rows + 1) squares, the image's x and y along the board's.
cv::Mat DrawCharucoBoard(const CharucoOptions& options, int pixels_per_square);

// The corners found in a grey image (CV_8UC1), each with its id (its index in
// ChessboardCorners(options.corners)); none when fewer than six, or all on one line.
std::optional<TargetView> DetectCharuco(const cv::Mat& grey, const CharucoOptions& options);

}  // namespace ts
