#include "processing/cloud/grid_index.h"

#include <cmath>
#include <limits>

namespace ts {

GridIndex::GridIndex(const std::vector<Eigen::Vector3d>& points, double cell_m) : cell_m_(cell_m) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) continue;
    min_x = std::min(min_x, p.x()), max_x = std::max(max_x, p.x());
    min_y = std::min(min_y, p.y()), max_y = std::max(max_y, p.y());
  }
  if (!(max_x >= min_x)) {  // no finite point
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
