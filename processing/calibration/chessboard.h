#pragma once
// Chessboard calibration targets: the board's inner corners in its own plane (z = 0, x along
// the columns, y along the rows, in the unit of the square), and their detection in an image
// by OpenCV's sector-based detector (findChessboardCornersSB: sub-pixel without cornerSubPix,
// robust to blur and uneven light). A view where the whole board is not found is reported, not
// fatal: calibration goes on with the others.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/options.h"

namespace ts {

struct ChessboardOptions {
  int columns = 9;  // inner corners along a row
  int rows = 6;     // inner corners along a column
  double square = 1.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("columns", self.columns, {"inner corners along a row", "", 3, 200});
    v("rows", self.rows, {"inner corners along a column", "", 3, 200});
    v("square", self.square, {"side of a square, in the unit of the results", "", 1e-9, 1e9});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

// "9x6" -> columns 9, rows 6; false if the text is not COLUMNSxROWS.
bool ParseBoardSize(const std::string& text, ChessboardOptions* options);

// The inner corners in the board's frame, row by row (the order of the detections).
std::vector<Eigen::Vector3d> ChessboardCorners(const ChessboardOptions& options);

// The inner corners in a grey image (CV_8UC1), in the order of ChessboardCorners; none when
// the whole board is not found.
std::optional<std::vector<Eigen::Vector2d>> DetectChessboard(const cv::Mat& grey,
                                                             const ChessboardOptions& options);

}  // namespace ts
