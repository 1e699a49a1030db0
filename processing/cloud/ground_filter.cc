#include "processing/cloud/ground_filter.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "processing/cloud/fill_holes.h"
#include "processing/cloud/grid_index.h"

namespace ts {

GroundFilterOptions GroundFilterOptions::ForTripod() {
  GroundFilterOptions g;
  g.elevation_threshold_m = 0.2;
  // The provisional ground is the lowest point of each cell: on a slope s the points of one
  // cell spread over s x cell_m above it, and all of them are ground (steep terrain's points
  // were cut as objects with less).
  g.elevation_scaler = g.cell_m;
  g.slope = 0.08;
  g.slope_from_terrain = true;
  return g;
}

bool GroundFilterOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!(max_window_m >= cell_m)) err = "max_window_m must be at least one cell";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

// Bilinear interpolation between cell centres, clamped to the grid.
float Sample(const cv::Mat& grid, double col_f, double row_f) {
  col_f = std::clamp(col_f, 0.0, grid.cols - 1.0);
  row_f = std::clamp(row_f, 0.0, grid.rows - 1.0);
  const int c0 = std::min(static_cast<int>(col_f), std::max(0, grid.cols - 2));
  const int r0 = std::min(static_cast<int>(row_f), std::max(0, grid.rows - 2));
  const int c1 = std::min(c0 + 1, grid.cols - 1), r1 = std::min(r0 + 1, grid.rows - 1);
  const float tx = static_cast<float>(col_f - c0), ty = static_cast<float>(row_f - r0);
  const float a = grid.at<float>(r0, c0) + tx * (grid.at<float>(r0, c1) - grid.at<float>(r0, c0));
  const float b = grid.at<float>(r1, c0) + tx * (grid.at<float>(r1, c1) - grid.at<float>(r1, c0));
  return a + ty * (b - a);
}

// The filled cells near known objects, lowered by object_shadow_fall times their distance
// from the nearest cell seen.
void LowerObjectShadows(const GridIndex& grid, const cv::Mat& known,
                        const std::vector<Eigen::Vector3d>& known_objects,
                        const GroundFilterOptions& o, cv::Mat* surface) {
  cv::Mat shadow(known.size(), CV_8UC1, cv::Scalar(0));
  for (const Eigen::Vector3d& q : known_objects) {
    const int c = grid.ColOf(q.x()), r = grid.RowOf(q.y());
    if (grid.Inside(c, r)) shadow.at<uint8_t>(r, c) = 1;
  }
  const int reach = static_cast<int>(std::lround(o.object_shadow_m / o.cell_m));
  cv::dilate(shadow, shadow,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * reach + 1, 2 * reach + 1}));
  shadow.setTo(0, known);
  cv::Mat distance;  // in cells, to the nearest cell seen
  cv::distanceTransform(known == 0, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const cv::Mat lowered = *surface - distance * (o.object_shadow_fall * o.cell_m);
  lowered.copyTo(*surface, shadow);
}

// The surface continued past its borders as the slope it ends on (a point reflection about each
// border cell): a slope cut off by the cloud's end is no cliff, and the opening must not take
// its upper edge for an object, as it would next to a flat (replicated) border.
cv::Mat ContinuedPastBorders(const cv::Mat& surface, int pad) {
  cv::Mat wide, tall;
  cv::copyMakeBorder(surface, wide, 0, 0, pad, pad, cv::BORDER_REFLECT_101);
  for (int r = 0; r < wide.rows; ++r) {
    const float left = wide.at<float>(r, pad), right = wide.at<float>(r, wide.cols - 1 - pad);
    for (int k = 0; k < pad; ++k) {
      wide.at<float>(r, k) = 2 * left - wide.at<float>(r, k);
      wide.at<float>(r, wide.cols - 1 - k) = 2 * right - wide.at<float>(r, wide.cols - 1 - k);
    }
  }
  cv::copyMakeBorder(wide, tall, pad, pad, 0, 0, cv::BORDER_REFLECT_101);
  for (int c = 0; c < tall.cols; ++c) {
    const float top = tall.at<float>(pad, c), bottom = tall.at<float>(tall.rows - 1 - pad, c);
    for (int k = 0; k < pad; ++k) {
      tall.at<float>(k, c) = 2 * top - tall.at<float>(k, c);
      tall.at<float>(tall.rows - 1 - k, c) = 2 * bottom - tall.at<float>(tall.rows - 1 - k, c);
    }
  }
  return tall;
}

// Per cell of `surface` (padded as the opening sees it), the steepest rise over run an opening
// may lower it by without taking it for an object: `slope`, or the terrain's regional gradient
// where that is steeper (ground_filter.h).
cv::Mat SlopeAllowance(const cv::Mat& surface, int max_radius, const GroundFilterOptions& o) {
  cv::Mat allowance(surface.size(), CV_32FC1, cv::Scalar(static_cast<float>(o.slope)));
  if (!o.slope_from_terrain) return allowance;
  const int width = 2 * max_radius + 1;
  cv::Mat terrain, gx, gy, gradient;
  cv::morphologyEx(surface, terrain, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(width, width)),
                   cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  cv::blur(terrain, terrain, cv::Size(width, width), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::Sobel(terrain, gx, CV_32F, 1, 0, 3, 1.0 / (8.0 * o.cell_m), 0, cv::BORDER_REPLICATE);
  cv::Sobel(terrain, gy, CV_32F, 0, 1, 3, 1.0 / (8.0 * o.cell_m), 0, cv::BORDER_REPLICATE);
  cv::magnitude(gx, gy, gradient);
  return cv::max(allowance, gradient);
}

}  // namespace

GroundFilterResult FilterGround(const std::vector<Eigen::Vector3d>& points,
                                const GroundFilterOptions& o,
                                const std::vector<Eigen::Vector3d>& known_objects) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("GroundFilterOptions: " + why);
  GroundFilterResult result;
  result.ground.assign(points.size(), 0);
  const GridIndex grid(points, o.cell_m);
  if (grid.cols() == 0) return result;
  result.min_x_m = grid.min_x_m(), result.min_y_m = grid.min_y_m(), result.cell_m = o.cell_m;

  // 1. Minimum surface.
  cv::Mat lowest(grid.rows(), grid.cols(), CV_32FC1, cv::Scalar(0));
  cv::Mat known(grid.rows(), grid.cols(), CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      double z = std::numeric_limits<double>::infinity();
      for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i)
        z = std::min(z, points[*i].z());
      if (std::isfinite(z))
        lowest.at<float>(r, c) = static_cast<float>(z), known.at<uint8_t>(r, c) = 1;
    }
  cv::Mat surface = FillHoles(lowest, known);
  if (o.object_shadow_m > 0.0 && !known_objects.empty())
    LowerObjectShadows(grid, known, known_objects, o, &surface);

  // 2. Progressive opening: cells an opening lowers by more than the slope allows are objects.
  cv::Mat object(grid.rows(), grid.cols(), CV_8UC1, cv::Scalar(0));
  const int max_radius = std::max(1, static_cast<int>(std::lround(o.max_window_m / o.cell_m)));
  const int pad = std::min(max_radius, std::min(grid.rows(), grid.cols()) - 1);
  const cv::Rect inside(pad, pad, grid.cols(), grid.rows());
  cv::Mat last = ContinuedPastBorders(surface, pad), opened;
  const cv::Mat allowance = SlopeAllowance(last, max_radius, o)(inside);
  for (int radius = 1; radius <= max_radius; ++radius) {
    const cv::Mat disk =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
    cv::morphologyEx(last, opened, cv::MORPH_OPEN, disk, cv::Point(-1, -1), 1,
                     cv::BORDER_REPLICATE);
    object.setTo(1, (last(inside) - opened(inside)) > allowance * (radius * o.cell_m));
    std::swap(last, opened);
  }

  // 3. Provisional ground: the minimum surface without the object cells, inpainted.
  known.setTo(0, object);
  result.surface = FillHoles(lowest, known);

  // 4. Points near the provisional ground (allowing for its local slope) are ground.
  cv::Mat gx, gy, slope;
  cv::Sobel(result.surface, gx, CV_32F, 1, 0, 3, 1.0 / (8.0 * o.cell_m), 0, cv::BORDER_REPLICATE);
  cv::Sobel(result.surface, gy, CV_32F, 0, 1, 3, 1.0 / (8.0 * o.cell_m), 0, cv::BORDER_REPLICATE);
  cv::magnitude(gx, gy, slope);
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    if (!p.allFinite()) continue;
    const double col_f = (p.x() - grid.min_x_m()) / o.cell_m - 0.5;
    const double row_f = (p.y() - grid.min_y_m()) / o.cell_m - 0.5;
    const double threshold =
        o.elevation_threshold_m + o.elevation_scaler * Sample(slope, col_f, row_f);
    result.ground[i] = std::abs(p.z() - Sample(result.surface, col_f, row_f)) <= threshold;
  }
  return result;
}

}  // namespace ts
