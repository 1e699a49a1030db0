#include "processing/cloud/height_blunder_filter.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <stdexcept>

#include "processing/cloud/grid_index.h"

namespace ts {

bool HeightBlunderOptions::Check(std::string* why) const {
  return CheckDeclaredOptions(*this, why);
}

std::vector<uint8_t> FindHeightBlunders(const std::vector<Eigen::Vector3d>& points,
                                        const HeightBlunderOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("HeightBlunderOptions: " + why);
  std::vector<uint8_t> blunder(points.size(), 0);
  constexpr int kReach = 2;  // cells each side: the window is 5 cells wide
  const GridIndex grid(points, o.window_m / (2 * kReach + 1));
  // Rows of cells in parallel: each cell judges only its own points.
  cv::parallel_for_(cv::Range(0, grid.rows()), [&](const cv::Range& rows) {
    std::vector<double> heights;
    for (int row = rows.start; row < rows.end; ++row)
      for (int col = 0; col < grid.cols(); ++col) {
        if (grid.Count(col, row) == 0) continue;
        int total = 0;
        for (int r = row - kReach; r <= row + kReach; ++r)
          for (int c = col - kReach; c <= col + kReach; ++c)
            if (grid.Inside(c, r)) total += grid.Count(c, r);
        if (total < o.min_neighbours + 1) continue;
        const int stride = std::max(1, total / o.max_samples);
        heights.clear();
        int k = 0;
        for (int r = row - kReach; r <= row + kReach; ++r)
          for (int c = col - kReach; c <= col + kReach; ++c) {
            if (!grid.Inside(c, r)) continue;
            for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i, ++k)
              if (k % stride == 0) heights.push_back(points[*i].z());
          }
        std::sort(heights.begin(), heights.end());
        const double median = heights[heights.size() / 2];
        for (const int* i = grid.begin(col, row); i != grid.end(col, row); ++i) {
          const double z = points[*i].z();
          if (std::abs(z - median) <= o.threshold_m) continue;
          if (o.min_layer_points > 0) {
            // Points of the window near its height (from the sample, itself included once).
            const auto layer =
                std::upper_bound(heights.begin(), heights.end(), z + o.layer_tolerance_m) -
                std::lower_bound(heights.begin(), heights.end(), z - o.layer_tolerance_m);
            if (static_cast<double>(layer) * stride - 1 >= o.min_layer_points) continue;
          }
          blunder[*i] = 1;
        }
      }
  });
  return blunder;
}

}  // namespace ts
