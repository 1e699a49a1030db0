#include "processing/calibration/chessboard.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/calib3d.hpp>

#include "processing/calibration/board_lattice.h"
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

std::array<Eigen::Vector2i, 3> CircleMarkerCells(const ChessboardOptions& o) {
  // The corner the three marker squares share, (i + 1, j + 1), nearest the board's centre;
  // every corner of the three squares an inner corner.
  const Eigen::Vector2d centre(0.5 * (o.columns - 1), 0.5 * (o.rows - 1));
  Eigen::Vector2i origin(0, 0);
  double nearest = 1e300;
  for (int j = 0; j + 2 < o.rows; ++j)
    for (int i = 0; i + 2 < o.columns; ++i) {
      if ((i + j) % 2 == 0) continue;  // a black square
      const double d = (Eigen::Vector2d(i + 1, j + 1) - centre).squaredNorm();
      if (d < nearest - 1e-9) {
        nearest = d;
        origin = {i, j};
      }
    }
  return {origin, origin + Eigen::Vector2i(1, 0), origin + Eigen::Vector2i(0, 1)};
}

bool ChessboardOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (circle_markers && columns < 4 && rows < 4) {
    if (why) *why = "circle_markers needs a board of at least 4 inner corners one way";
    return false;
  }
  return true;
}

namespace {

// The shortest side of a square in the image, from neighbouring corners.
double ShortestSquareSide(const CornerGrid& g) {
  double shortest = 1e30;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.columns; ++c) {
      if (c + 1 < g.columns) shortest = std::min(shortest, (g.at(c + 1, r) - g.at(c, r)).norm());
      if (r + 1 < g.rows) shortest = std::min(shortest, (g.at(c, r + 1) - g.at(c, r)).norm());
    }
  return shortest;
}

// The sector-based detector's corners are biased on strongly tilted, anti-aliased boards (on
// simulated boards tilted up to 50 deg: 44 of 3800 corners rejected as > 5 sigma0, the
// principal distance 4 sigma off). The gradient-orthogonality refinement (saddle_refinement.h)
// is unbiased for an X-junction under any affine view of it, as long as its window holds that
// junction alone: a third of the shortest square side (a circle marker, at a square's centre
// with a radius of 0.17 square, is beyond it). A corner it cannot fix (its window off the
// frame) keeps the detector's place, and is flagged in `refined`.
CornerGrid RefinedGrid(const cv::Mat& grey, const std::vector<cv::Point2f>& found, int columns,
                       int rows, std::vector<bool>* refined) {
  CornerGrid g{columns, rows, {}};
  for (const cv::Point2f& p : found) g.corners.emplace_back(p.x, p.y);
  const double half = ShortestSquareSide(g) / 3.0;
  std::vector<Eigen::Vector2d> corners = g.corners;
  RefineSaddles(grey, std::vector<double>(corners.size(), half), {}, {}, &corners, refined);
  for (size_t k = 0; k < refined->size(); ++k)
    if ((*refined)[k]) g.corners[k] = corners[k];
  return g;
}

constexpr int kDetectorFlags =
    cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY;

// The whole board, ids in the order of ChessboardCorners.
std::optional<TargetView> DetectWholeBoard(const cv::Mat& grey, const ChessboardOptions& o) {
  std::vector<cv::Point2f> found;
  if (!cv::findChessboardCornersSB(grey, cv::Size(o.columns, o.rows), found, kDetectorFlags))
    return {};
  if (found.size() != static_cast<size_t>(o.columns * o.rows)) return {};
  TargetView view;
  std::vector<bool> refined;
  view.pixels = RefinedGrid(grey, found, o.columns, o.rows, &refined).corners;
  for (size_t k = 0; k < view.pixels.size(); ++k) view.ids.push_back(static_cast<int>(k));
  return view;
}

// The part of a board with circle markers in view: any grid of 3 x 3 corners or more
// (CALIB_CB_LARGER; `meta` has its size), checked to be the board's lattice and numbered by
// its markers (board_lattice.h). With CALIB_CB_MARKER the detector grows its grid across the
// markers' squares, but it refuses some boards whose markers are in plain view; without it the
// grid may stop short of them. The first grid that holds them counts.
std::optional<TargetView> DetectMarkedBoard(const cv::Mat& grey, const ChessboardOptions& o) {
  for (const int markers : {static_cast<int>(cv::CALIB_CB_MARKER), 0}) {
    std::vector<cv::Point2f> found;
    cv::Mat meta;
    const int flags = kDetectorFlags | cv::CALIB_CB_LARGER | markers;
    if (!cv::findChessboardCornersSB(grey, cv::Size(3, 3), found, flags, meta)) continue;
    if (found.size() != meta.total()) continue;
    std::vector<bool> refined;
    const CornerGrid grid = RefinedGrid(grey, found, meta.cols, meta.rows, &refined);
    const GridSquares squares = SampleSquares(grey, grid);
    if (!IsBoardLattice(squares)) continue;
    const std::optional<std::vector<int>> ids = NumberByCircleMarkers(grid, squares, o);
    if (!ids) continue;
    // A part of a board reaches the frame's edge, where a corner's window leaves the frame
    // and the detector's place is all there is: such corners are left out.
    TargetView view;
    for (size_t k = 0; k < ids->size(); ++k)
      if (refined[k]) {
        view.ids.push_back((*ids)[k]);
        view.pixels.push_back(grid.corners[k]);
      }
    return view;
  }
  return {};
}

}  // namespace

std::optional<TargetView> DetectChessboard(const cv::Mat& grey, const ChessboardOptions& o) {
  return o.circle_markers ? DetectMarkedBoard(grey, o) : DetectWholeBoard(grey, o);
}

}  // namespace ts
