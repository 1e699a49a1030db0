#include "processing/products/map_drawing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace ts {

cv::Mat ComputeHillshade(const Raster& dem, const HillshadeOptions& o) {
  const double az = (90.0 - o.sun_azimuth_deg) * M_PI / 180.0;  // from +x, counter-clockwise
  const double el = o.sun_elevation_deg * M_PI / 180.0;
  const Eigen::Vector3d sun(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  auto height = [&](int r, int c, float fallback) {
    r = std::clamp(r, 0, dem.rows - 1), c = std::clamp(c, 0, dem.cols - 1);
    const float v = dem.at(r, c);
    return Raster::IsNoData(v) ? fallback : v;
  };
  cv::Mat shade(dem.rows, dem.cols, CV_32FC1, cv::Scalar(NAN));
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const float z = dem.at(r, c);
      if (Raster::IsNoData(z)) continue;
      const double dzdx = (height(r, c + 1, z) - height(r, c - 1, z)) / (2 * dem.cell_m);
      const double dzdy = (height(r - 1, c, z) - height(r + 1, c, z)) / (2 * dem.cell_m);
      const Eigen::Vector3d normal =
          Eigen::Vector3d(-o.vertical_exaggeration * dzdx, -o.vertical_exaggeration * dzdy, 1)
              .normalized();
      shade.at<float>(r, c) = static_cast<float>(std::max(0.0, normal.dot(sun)));
    }
  return shade;
}

void DrawStationMarker(cv::Mat* image, const Raster& grid, int k,
                       const Eigen::Vector2d& station_xy_m) {
  const double sx = (station_xy_m.x() - grid.min_x_m) / grid.cell_m * k;
  const double sy = (grid.max_y_m - station_xy_m.y()) / grid.cell_m * k;
  const std::vector<cv::Point> triangle = {cv::Point(sx, sy - 9), cv::Point(sx - 8, sy + 6),
                                           cv::Point(sx + 8, sy + 6)};
  cv::fillConvexPoly(*image, triangle, cv::Scalar(255, 255, 255), cv::LINE_AA);
  cv::polylines(*image, triangle, true, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
}

void DrawScaleBarAndText(cv::Mat* image, const Raster& grid, int k, int y0,
                         const std::string& text) {
  const double bar_m = std::min(10.0, grid.cols * grid.cell_m / 5.0);
  const int bar_px = static_cast<int>(bar_m / grid.cell_m * k);
  cv::rectangle(*image, cv::Rect(10, y0, bar_px, 6), cv::Scalar(0, 0, 0), cv::FILLED);
  char label[32];
  std::snprintf(label, sizeof label, "%.0f m", bar_m);
  cv::putText(*image, label, cv::Point(16 + bar_px, y0 + 8), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(*image, text, cv::Point(90 + bar_px, y0 + 8), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

}  // namespace ts
