#include "processing/calibration/chessboard.h"

#include <cstdio>
#include <opencv2/calib3d.hpp>

namespace ts {

bool ParseBoardSize(const std::string& text, ChessboardOptions* options) {
  int columns = 0, rows = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &columns, &rows, &tail) != 2) return false;
  options->columns = columns;
  options->rows = rows;
  return true;
}

std::vector<Eigen::Vector3d> ChessboardCorners(const ChessboardOptions& o) {
  std::vector<Eigen::Vector3d> corners;
  for (int r = 0; r < o.rows; ++r)
    for (int c = 0; c < o.columns; ++c) corners.emplace_back(c * o.square, r * o.square, 0.0);
  return corners;
}

std::optional<std::vector<Eigen::Vector2d>> DetectChessboard(const cv::Mat& grey,
                                                             const ChessboardOptions& o) {
  std::vector<cv::Point2f> found;
  const int flags = cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY;
  if (!cv::findChessboardCornersSB(grey, cv::Size(o.columns, o.rows), found, flags)) return {};
  if (found.size() != static_cast<size_t>(o.columns * o.rows)) return {};
  std::vector<Eigen::Vector2d> corners;
  for (const cv::Point2f& p : found) corners.emplace_back(p.x, p.y);
  return corners;
}

}  // namespace ts
