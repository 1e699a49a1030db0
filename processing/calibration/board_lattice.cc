#include "processing/calibration/board_lattice.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace ts {
namespace {

// Where in a square (0..1 along each side) it is sampled: its level away from the edges,
// which blur, and from a circle marker; its centre well within the marker.
constexpr double kLevelAt[] = {0.25, 0.42, 0.58, 0.75};
constexpr double kMarkerClearance = 0.5 * kCircleMarkerDiameter + 0.05;
constexpr double kCentreAt[][2] = {{0.5, 0.5}, {0.44, 0.5}, {0.56, 0.5}, {0.5, 0.44}, {0.5, 0.56}};

// The places of a square's samples: its level's, then its centre's (`levels` of them first).
std::vector<std::array<double, 2>> SamplePlaces(int* levels) {
  std::vector<std::array<double, 2>> places;
  for (double v : kLevelAt)
    for (double u : kLevelAt)
      if (std::hypot(u - 0.5, v - 0.5) >= kMarkerClearance) places.push_back({u, v});
  *levels = static_cast<int>(places.size());
  for (const auto& [u, v] : kCentreAt) places.push_back({u, v});
  return places;
}

Eigen::Vector2d InSquare(const CornerGrid& g, int c, int r, double u, double v) {
  return (1 - u) * (1 - v) * g.at(c, r) + u * (1 - v) * g.at(c + 1, r) +
         (1 - u) * v * g.at(c, r + 1) + u * v * g.at(c + 1, r + 1);
}

}  // namespace

GridSquares SampleSquares(const cv::Mat& grey, const CornerGrid& g) {
  GridSquares s;
  s.columns = std::max(0, g.columns - 1);
  s.rows = std::max(0, g.rows - 1);
  const int n = s.columns * s.rows;
  if (n == 0) return s;
  int levels = 0;
  const std::vector<std::array<double, 2>> places = SamplePlaces(&levels);
  const int per_square = static_cast<int>(places.size());
  std::vector<cv::Point2f> samples;
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.columns; ++c)
      for (const auto& [u, v] : places) {
        const Eigen::Vector2d p = InSquare(g, c, r, u, v);
        samples.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
      }
  cv::Mat values;
  cv::remap(grey, values, cv::Mat(samples), cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  values.convertTo(values, CV_64F);
  for (int k = 0; k < n; ++k) {
    const cv::Mat level = values.rowRange(k * per_square, k * per_square + levels);
    const cv::Mat centre = values.rowRange(k * per_square + levels, (k + 1) * per_square);
    double low = 0, high = 0;
    cv::minMaxLoc(level, &low, &high);
    s.level.push_back(cv::mean(level)[0]);
    s.spread.push_back(high - low);
    s.centre.push_back(cv::mean(centre)[0]);
  }
  const auto [dark, light] = std::minmax_element(s.level.begin(), s.level.end());
  s.dark = *dark;
  s.light = *light;
  return s;
}

bool IsBoardLattice(const GridSquares& s) {
  const int n = s.columns * s.rows;
  const double contrast = s.Contrast(), middle = s.Middle();
  if (n == 0 || contrast <= 0) return false;
  const bool first_dark = s.level[0] < middle;
  int good = 0;
  for (int k = 0; k < n; ++k) {
    const bool even = (k % s.columns + k / s.columns) % 2 == 0;
    good += s.spread[k] < 0.5 * contrast && (s.level[k] < middle) == (first_dark == even);
  }
  return good >= 0.9 * n;
}

std::optional<std::vector<int>> NumberByCircleMarkers(const CornerGrid& g, const GridSquares& s,
                                                      const ChessboardOptions& board) {
  const double contrast = s.Contrast(), middle = s.Middle();
  std::vector<Eigen::Vector2i> origin, axes;  // squares with a dark, a light circle
  for (int k = 0; k < s.columns * s.rows; ++k) {
    if (std::abs(s.centre[k] - s.level[k]) < 0.5 * contrast) continue;
    const Eigen::Vector2i square(k % s.columns, k / s.columns);
    (s.level[k] > middle ? origin : axes).push_back(square);
  }
  if (origin.size() != 1 || axes.size() != 2) return std::nullopt;
  const Eigen::Vector2i d1 = axes[0] - origin[0], d2 = axes[1] - origin[0];
  if (d1.lpNorm<1>() != 1 || d2.lpNorm<1>() != 1 || d1.dot(d2) != 0) return std::nullopt;
  // The board's x and y in the grid, told apart by their turn in the image.
  const auto centre_of = [&](const Eigen::Vector2i& q) {
    return InSquare(g, q.x(), q.y(), 0.5, 0.5);
  };
  const Eigen::Vector2d o = centre_of(origin[0]);
  const Eigen::Vector2d v1 = centre_of(axes[0]) - o, v2 = centre_of(axes[1]) - o;
  const bool first_is_x = v1.x() * v2.y() - v1.y() * v2.x() > 0;
  const Eigen::Vector2i ex = first_is_x ? d1 : d2, ey = first_is_x ? d2 : d1;
  // The origin square's top left corner on the board is its corner towards -x and -y.
  const Eigen::Vector2i q0 = origin[0] + (Eigen::Vector2i::Ones() - ex - ey) / 2;
  const Eigen::Vector2i b0 = CircleMarkerCells(board)[0];
  std::vector<int> ids;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.columns; ++c) {
      const Eigen::Vector2i q = Eigen::Vector2i(c, r) - q0;
      const int column = b0.x() + ex.dot(q), row = b0.y() + ey.dot(q);
      if (column < 0 || column >= board.columns || row < 0 || row >= board.rows)
        return std::nullopt;
      ids.push_back(row * board.columns + column);
    }
  return ids;
}

}  // namespace ts
