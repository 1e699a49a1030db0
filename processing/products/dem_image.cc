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
  cv::Mat colour_index(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) colour_index.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
  cv::Mat palette;
  cv::applyColorMap(colour_index, palette, cv::COLORMAP_TURBO);
  const cv::Mat shade = ComputeHillshade(dem, o.shade);
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const float z = dem.at(r, c);
      cv::Vec3b colour(160, 160, 160);
      if (!Raster::IsNoData(z)) {
        const double light = 0.35 + 0.65 * shade.at<float>(r, c);
        const int index = hi > lo ? static_cast<int>(255.0 * (z - lo) / (hi - lo)) : 128;
        const cv::Vec3b base = palette.at<cv::Vec3b>(0, std::clamp(index, 0, 255));
        for (int ch = 0; ch < 3; ++ch) colour[ch] = cv::saturate_cast<uint8_t>(base[ch] * light);
      }
      image(cv::Rect(c * k, r * k, k, k)).setTo(colour);
    }
  DrawStationMarker(&image, dem, k, station_xy_m);
  char text[160];
  if (any)
    std::snprintf(text, sizeof text, "height %.2f .. %.2f m (blue to red)", lo, hi);
  else
    std::snprintf(text, sizeof text, "no data");
  DrawScaleBarAndText(&image, dem, k, dem.rows * k + 12, text);
  return image;
}

}  // namespace ts
