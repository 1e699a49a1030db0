#pragma once
// Chessboard calibration targets: the board's inner corners in its own plane (z = 0, x along
// the columns, y along the rows, in the unit of the square), and their detection in an image
// by OpenCV's sector-based detector (findChessboardCornersSB: sub-pixel without cornerSubPix,
// robust to blur and uneven light). A view where the board is not found is reported, not fatal:
// calibration goes on with the others.
//
// A plain chessboard counts only when all of it is in view. A board carrying OpenCV's three
// circle markers (gen_pattern.py's radon_checkerboard) counts in part too: the markers name its
// corners, so it can be held running off the frame, where the distortion is largest.
#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/calibration/target_views.h"

namespace ts {

struct ChessboardOptions {
  int columns = 9;  // inner corners along a row
  int rows = 6;     // inner corners along a column
  double square = 1.0;
  // The three circle markers at the board's centre (CircleMarkerCells).
  bool circle_markers = false;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("columns", self.columns, {"inner corners along a row", "", 3, 200});
    v("rows", self.rows, {"inner corners along a column", "", 3, 200});
    v("square", self.square, {"side of a square, in the unit of the results", "", 1e-9, 1e9});
    v("circle_markers", self.circle_markers,
      {"the board carries three circle markers at its centre; views of a part of it count"});
  }
  bool Check(std::string* why) const;
};

// "9x6" -> columns 9, rows 6; false if the text is not COLUMNSxROWS.
bool ParseBoardSize(const std::string& text, ChessboardOptions* options);

// The inner corners in the board's frame, row by row (the order of the detections).
std::vector<Eigen::Vector3d> ChessboardCorners(const ChessboardOptions& options);

// The squares (column, row; the first square, black, is (-1, -1): square (i, j) has inner
// corner (i, j) at its top left) that carry a circle marker, as OpenCV's detector wants them:
// the origin, a white square with a black circle, first; then the black squares right of it
// and below it, with white circles. The origin is the white square nearest the board's centre
// whose two neighbours are on the board, so that a part of the board about its centre, the part
// every view of it holds, names its corners. Circles have a diameter of 0.34 square.
std::array<Eigen::Vector2i, 3> CircleMarkerCells(const ChessboardOptions& options);
inline constexpr double kCircleMarkerDiameter = 0.34;  // of a square

// The inner corners in a grey image (CV_8UC1) with their ids (the index in ChessboardCorners).
// A plain board: all of them or none. A board with circle markers: the part in view when the
// markers are in it, none when they are not or the part does not fit the board.
std::optional<TargetView> DetectChessboard(const cv::Mat& grey, const ChessboardOptions& options);

}  // namespace ts
