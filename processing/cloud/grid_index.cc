#include "processing/cloud/grid_index.h"

#include <cmath>
#include <limits>

namespace ts {

namespace {

struct Bounds {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  bool Empty() const { return !(max_x >= min_x); }
};

Bounds BoundsOf(const std::vector<Eigen::Vector3d>& points) {
  Bounds b;
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) continue;
    b.min_x = std::min(b.min_x, p.x()), b.max_x = std::max(b.max_x, p.x());
    b.min_y = std::min(b.min_y, p.y()), b.max_y = std::max(b.max_y, p.y());
  }
  return b;
}

}  // namespace

double GridIndex::CellsFor(const std::vector<Eigen::Vector3d>& points, double cell_m) {
  const Bounds b = BoundsOf(points);
  if (b.Empty()) return 0.0;
  return (std::floor((b.max_x - b.min_x) / cell_m) + 1) *
         (std::floor((b.max_y - b.min_y) / cell_m) + 1);
}

GridIndex::GridIndex(const std::vector<Eigen::Vector3d>& points, double cell_m) : cell_m_(cell_m) {
  const Bounds b = BoundsOf(points);
  const double min_x = b.min_x, min_y = b.min_y, max_x = b.max_x, max_y = b.max_y;
  if (b.Empty()) {  // no finite point
    start_.assign(1, 0);
    return;
  }
  min_x_m_ = min_x, min_y_m_ = min_y;
  cols_ = static_cast<int>(std::floor((max_x - min_x) / cell_m)) + 1;
  rows_ = static_cast<int>(std::floor((max_y - min_y) / cell_m)) + 1;
  // Counting sort into cells.
  std::vector<int> cell_of(points.size(), -1);
  start_.assign(static_cast<size_t>(cols_) * rows_ + 1, 0);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    const int c = std::min(cols_ - 1, ColOf(points[i].x()));
    const int r = std::min(rows_ - 1, RowOf(points[i].y()));
    cell_of[i] = Cell(c, r);
    ++start_[cell_of[i] + 1];
  }
  for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  order_.resize(start_.back());
  std::vector<int> next(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i)
    if (cell_of[i] >= 0) order_[next[cell_of[i]]++] = static_cast<int>(i);
}

int GridIndex::ColOf(double x_m) const {
  return static_cast<int>(std::floor((x_m - min_x_m_) / cell_m_));
}

int GridIndex::RowOf(double y_m) const {
  return static_cast<int>(std::floor((y_m - min_y_m_) / cell_m_));
}

}  // namespace ts
