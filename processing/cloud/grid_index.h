#pragma once
// Points of a cloud bucketed by a horizontal grid (x, y), for neighbourhood queries: the
// blunder filter, the ground filter and kriging share it. Cells are cell_m squares starting
// at (min_x_m, min_y_m); the points of cell (col, row) are order[start[c] .. start[c + 1]).
#include <Eigen/Core>
#include <vector>

namespace ts {

class GridIndex {
 public:
  // Bounds from the points themselves; cell_m > 0. Non-finite points are left out.
  GridIndex(const std::vector<Eigen::Vector3d>& points, double cell_m);
  // The cells such a grid would have (0 without a finite point), counted before allocating.
  static double CellsFor(const std::vector<Eigen::Vector3d>& points, double cell_m);

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  double cell_m() const { return cell_m_; }
  double min_x_m() const { return min_x_m_; }
  double min_y_m() const { return min_y_m_; }
  int ColOf(double x_m) const;  // may lie outside [0, cols)
  int RowOf(double y_m) const;  // row 0 is the southern edge here (y grows with row)
  bool Inside(int col, int row) const { return col >= 0 && row >= 0 && col < cols_ && row < rows_; }
  // Indices (into the points given) of the points of one cell.
  const int* begin(int col, int row) const { return order_.data() + start_[Cell(col, row)]; }
  const int* end(int col, int row) const { return order_.data() + start_[Cell(col, row) + 1]; }
  int Count(int col, int row) const { return start_[Cell(col, row) + 1] - start_[Cell(col, row)]; }

 private:
  int Cell(int col, int row) const { return row * cols_ + col; }
  double min_x_m_ = 0.0, min_y_m_ = 0.0, cell_m_ = 1.0;
  int cols_ = 0, rows_ = 0;
  std::vector<int> start_;  // cols * rows + 1
  std::vector<int> order_;
};

}  // namespace ts
