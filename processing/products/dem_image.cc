#include "processing/products/dem_image.h"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace ts {

cv::Mat RenderDemImage(const Raster& dem, const Eigen::Vector2d& station_xy_m,
                       const DemImageOptions& o) {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (float v : dem.values)
    if (!Raster::IsNoData(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  const bool any = hi >= lo;
  const int k = std::max(1, o.pixels_per_cell);
  const int legend_px = 40;
  cv::Mat image(dem.rows * k + legend_px, dem.cols * k, CV_8UC3, cv::Scalar(255, 255, 255));
  // Per cell: colour from the height, shade from the normal (Horn's 3x3 gradient).
  const double az = (90.0 - o.sun_azimuth_deg) * M_PI / 180.0;  // from +x, counter-clockwise
  const double el = o.sun_elevation_deg * M_PI / 180.0;
  const Eigen::Vector3d sun(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  cv::Mat colour_index(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) colour_index.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
  cv::Mat palette;
  cv::applyColorMap(colour_index, palette, cv::COLORMAP_TURBO);
  auto height = [&](int r, int c, float fallback) {
    r = std::clamp(r, 0, dem.rows - 1), c = std::clamp(c, 0, dem.cols - 1);
    const float v = dem.at(r, c);
    return Raster::IsNoData(v) ? fallback : v;
  };
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const float z = dem.at(r, c);
      cv::Vec3b colour(160, 160, 160);
      if (!Raster::IsNoData(z)) {
        const double dzdx = (height(r, c + 1, z) - height(r, c - 1, z)) / (2 * dem.cell_m);
        const double dzdy = (height(r - 1, c, z) - height(r + 1, c, z)) / (2 * dem.cell_m);
        const Eigen::Vector3d normal =
            Eigen::Vector3d(-o.vertical_exaggeration * dzdx, -o.vertical_exaggeration * dzdy, 1)
                .normalized();
        const double shade = 0.35 + 0.65 * std::max(0.0, normal.dot(sun));
        const int index = hi > lo ? static_cast<int>(255.0 * (z - lo) / (hi - lo)) : 128;
        const cv::Vec3b base = palette.at<cv::Vec3b>(0, std::clamp(index, 0, 255));
        for (int ch = 0; ch < 3; ++ch) colour[ch] = cv::saturate_cast<uint8_t>(base[ch] * shade);
      }
      image(cv::Rect(c * k, r * k, k, k)).setTo(colour);
    }
  // Station marker: a black-ringed white triangle.
  const double sx = (station_xy_m.x() - dem.min_x_m) / dem.cell_m * k;
  const double sy = (dem.max_y_m - station_xy_m.y()) / dem.cell_m * k;
  const std::vector<cv::Point> triangle = {cv::Point(sx, sy - 9), cv::Point(sx - 8, sy + 6),
                                           cv::Point(sx + 8, sy + 6)};
  cv::fillConvexPoly(image, triangle, cv::Scalar(255, 255, 255), cv::LINE_AA);
  cv::polylines(image, triangle, true, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
  // Scale bar of 10 m (or a fifth of the width) and the height range.
  const double bar_m = std::min(10.0, dem.cols * dem.cell_m / 5.0);
  const int bar_px = static_cast<int>(bar_m / dem.cell_m * k);
  const int y0 = dem.rows * k + 12;
  cv::rectangle(image, cv::Rect(10, y0, bar_px, 6), cv::Scalar(0, 0, 0), cv::FILLED);
  char text[160];
  std::snprintf(text, sizeof text, "%.0f m", bar_m);
  cv::putText(image, text, cv::Point(16 + bar_px, y0 + 8), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  if (any)
    std::snprintf(text, sizeof text, "height %.2f .. %.2f m (blue to red)", lo, hi);
  else
    std::snprintf(text, sizeof text, "no data");
  cv::putText(image, text, cv::Point(90 + bar_px, y0 + 8), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return image;
}

}  // namespace ts
