#include "processing/calibration/chessboard.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/calib3d.hpp>

#include "processing/calibration/saddle_refinement.h"

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

namespace {

// The shortest side of a square in the image, from neighbouring corners.
double ShortestSquareSide(const std::vector<cv::Point2f>& corners, const ChessboardOptions& o) {
  double shortest = 1e30;
  for (int r = 0; r < o.rows; ++r)
    for (int c = 0; c < o.columns; ++c) {
      const cv::Point2f& p = corners[r * o.columns + c];
      if (c + 1 < o.columns)
        shortest = std::min<double>(shortest, cv::norm(corners[r * o.columns + c + 1] - p));
      if (r + 1 < o.rows)
        shortest = std::min<double>(shortest, cv::norm(corners[(r + 1) * o.columns + c] - p));
    }
  return shortest;
}

// The sector-based detector's corners are biased on strongly tilted, anti-aliased boards (on
// simulated boards tilted up to 50 deg: 44 of 3800 corners rejected as > 5 sigma0, the
// principal distance 4 sigma off). The gradient-orthogonality refinement (saddle_refinement.h)
// is unbiased for an X-junction under any affine view of it, as long as its window holds that
// junction alone: a third of the shortest square side. A corner it cannot fix keeps the
// detector's place.
void RefineCorners(const cv::Mat& grey, const ChessboardOptions& o,
                   std::vector<cv::Point2f>* found) {
  const double half = ShortestSquareSide(*found, o) / 3.0;
  std::vector<Eigen::Vector2d> corners;
  for (const cv::Point2f& p : *found) corners.emplace_back(p.x, p.y);
  std::vector<bool> refined;
  RefineSaddles(grey, std::vector<double>(corners.size(), half), {}, {}, &corners, &refined);
  for (size_t k = 0; k < corners.size(); ++k)
    if (refined[k]) (*found)[k] = cv::Point2f(corners[k].x(), corners[k].y());
}

}  // namespace

std::optional<std::vector<Eigen::Vector2d>> DetectChessboard(const cv::Mat& grey,
                                                             const ChessboardOptions& o) {
  std::vector<cv::Point2f> found;
  const int flags = cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY;
  if (!cv::findChessboardCornersSB(grey, cv::Size(o.columns, o.rows), found, flags)) return {};
  if (found.size() != static_cast<size_t>(o.columns * o.rows)) return {};
  RefineCorners(grey, o, &found);
  std::vector<Eigen::Vector2d> corners;
  for (const cv::Point2f& p : found) corners.emplace_back(p.x, p.y);
  return corners;
}

}  // namespace ts
