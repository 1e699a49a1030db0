// The squares between detected corners: a grid is the board's lattice or refused, and a part of
// a board with circle markers is numbered by them in any orientation the detector returns it,
// on boards drawn here with the corners known exactly.
#include "processing/calibration/board_lattice.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "processing/calibration/chessboard.h"

namespace ts {
namespace {

constexpr double kSquarePx = 24.0;

// The board drawn turned by `angle_deg` about the image's centre (4x supersampled): its inner
// corner (c, r) at Corner(c, r).
struct DrawnBoard {
  ChessboardOptions board{16, 11, 1.0, true};
  double angle_deg = 0.0;
  cv::Mat grey;

  Eigen::Vector2d Corner(double c, double r) const {
    const double a = angle_deg * M_PI / 180.0;
    const Eigen::Vector2d p((c - 7.5) * kSquarePx, (r - 5.0) * kSquarePx);
    return Eigen::Vector2d(400, 400) + Eigen::Vector2d(std::cos(a) * p.x() - std::sin(a) * p.y(),
                                                       std::sin(a) * p.x() + std::cos(a) * p.y());
  }
};

DrawnBoard Draw(double angle_deg) {
  DrawnBoard d;
  d.angle_deg = angle_deg;
  constexpr int kScale = 4;
  cv::Mat big(800 * kScale, 800 * kScale, CV_8UC1, cv::Scalar(200));
  const auto polygon = [&](double c0, double r0, double c1, double r1) {
    std::vector<cv::Point> points;
    for (const auto& [c, r] : {std::pair{c0, r0}, {c1, r0}, {c1, r1}, {c0, r1}}) {
      const Eigen::Vector2d p = d.Corner(c, r) * kScale;
      points.emplace_back(static_cast<int>(std::lround(p.x())),
                          static_cast<int>(std::lround(p.y())));
    }
    return points;
  };
  for (int j = -1; j < d.board.rows; ++j)
    for (int i = -1; i < d.board.columns; ++i)
      if ((i + j) % 2 == 0) cv::fillConvexPoly(big, polygon(i, j, i + 1, j + 1), cv::Scalar(20));
  for (const Eigen::Vector2i& cell : CircleMarkerCells(d.board)) {
    const Eigen::Vector2d centre = d.Corner(cell.x() + 0.5, cell.y() + 0.5) * kScale;
    const bool black_square = (cell.x() + cell.y()) % 2 == 0;
    cv::circle(big, cv::Point(static_cast<int>(centre.x()), static_cast<int>(centre.y())),
               static_cast<int>(0.5 * kCircleMarkerDiameter * kSquarePx * kScale),
               cv::Scalar(black_square ? 200 : 20), cv::FILLED);
  }
  cv::resize(big, d.grey, cv::Size(800, 800), 0, 0, cv::INTER_AREA);
  return d;
}

// A grid of the board's corners (c0..c1, r0..r1) as a detector may return it: its rows along
// the board's rows or columns, either way along each.
CornerGrid GridOf(const DrawnBoard& d, int c0, int c1, int r0, int r1, bool transposed,
                  bool reverse_columns, bool reverse_rows, std::vector<int>* ids) {
  CornerGrid g;
  const int nc = c1 - c0 + 1, nr = r1 - r0 + 1;
  g.columns = transposed ? nr : nc;
  g.rows = transposed ? nc : nr;
  for (int gr = 0; gr < g.rows; ++gr)
    for (int gc = 0; gc < g.columns; ++gc) {
      int a = reverse_columns ? g.columns - 1 - gc : gc, b = reverse_rows ? g.rows - 1 - gr : gr;
      if (transposed) std::swap(a, b);
      const int c = c0 + a, r = r0 + b;
      g.corners.push_back(d.Corner(c, r));
      ids->push_back(r * d.board.columns + c);
    }
  return g;
}

TEST(BoardLattice, APartAboutTheMarkersIsNumberedInEveryOrientation) {
  for (const double angle : {0.0, 35.0, 100.0, 190.0, 280.0}) {
    const DrawnBoard d = Draw(angle);
    for (int order = 0; order < 8; ++order) {
      std::vector<int> truth;
      const CornerGrid g = GridOf(d, 3, 12, 2, 9, order & 1, order & 2, order & 4, &truth);
      const GridSquares squares = SampleSquares(d.grey, g);
      ASSERT_TRUE(IsBoardLattice(squares)) << angle << " " << order;
      const std::optional<std::vector<int>> ids = NumberByCircleMarkers(g, squares, d.board);
      // A grid in the mirrored order is still the board seen from its front: the turn from x to
      // y in the image tells them apart.
      ASSERT_TRUE(ids) << angle << " " << order;
      EXPECT_EQ(*ids, truth) << "angle " << angle << ", order " << order;
    }
  }
}

TEST(BoardLattice, WithoutAllThreeMarkersNothingIsNumbered) {
  const DrawnBoard d = Draw(20.0);
  const Eigen::Vector2i origin = CircleMarkerCells(d.board)[0];
  std::vector<int> ids;
  // The grid stops at the origin square's right edge: one of the three is outside it.
  const CornerGrid g = GridOf(d, 0, origin.x() + 1, 0, 10, false, false, false, &ids);
  const GridSquares squares = SampleSquares(d.grey, g);
  EXPECT_TRUE(IsBoardLattice(squares));
  EXPECT_FALSE(NumberByCircleMarkers(g, squares, d.board));
  // The whole board, declared smaller than it is: placed by its markers, the grid runs off it.
  ChessboardOptions narrower = d.board;
  narrower.columns = 12;
  std::vector<int> unused;
  const CornerGrid all = GridOf(d, 0, 15, 0, 10, false, false, false, &unused);
  EXPECT_FALSE(NumberByCircleMarkers(all, SampleSquares(d.grey, all), narrower));
}

// The detector's false lattice on strongly tilted boards: every other corner, turned by 45
// degrees, its cells across four squares. Refused; the true lattice of the same corners passes.
TEST(BoardLattice, AFalseLatticeOfEveryOtherCornerIsRefused) {
  const DrawnBoard d = Draw(10.0);
  CornerGrid diagonal{4, 4, {}};
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) diagonal.corners.push_back(d.Corner(4 + a + b, 5 + a - b));
  EXPECT_FALSE(IsBoardLattice(SampleSquares(d.grey, diagonal)));
  std::vector<int> ids;
  EXPECT_TRUE(
      IsBoardLattice(SampleSquares(d.grey, GridOf(d, 4, 10, 2, 8, false, false, false, &ids))));
}

}  // namespace
}  // namespace ts
