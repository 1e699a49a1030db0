#include "processing/products/dod_image.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

#include "processing/products/map_drawing.h"

namespace ts {
namespace {

// ColorBrewer RdBu ends and white, BGR: t in [-1, 1], -1 deep lowering (red).
cv::Vec3b Diverging(double t) {
  const cv::Vec3d red(43, 24, 178), blue(172, 102, 33), white(247, 247, 247);
  const double a = std::min(1.0, std::abs(t));
  const cv::Vec3d end = t < 0.0 ? red : blue;
  const cv::Vec3d c = white * (1.0 - a) + end * a;
  return cv::Vec3b(cv::saturate_cast<uint8_t>(c[0]), cv::saturate_cast<uint8_t>(c[1]),
                   cv::saturate_cast<uint8_t>(c[2]));
}

cv::Point ToPixel(const Raster& grid, int k, const Eigen::Vector2d& xy) {
  return cv::Point(static_cast<int>(std::lround((xy.x() - grid.min_x_m) / grid.cell_m * k)),
                   static_cast<int>(std::lround((grid.max_y_m - xy.y()) / grid.cell_m * k)));
}

}  // namespace

cv::Mat RenderDodImage(const ChangeResult& change, const Raster* shade_dem,
                       const std::optional<Eigen::Vector2d>& station_xy_m, int pixels_per_cell) {
  const Raster& dod = change.dod;
  const int k = std::max(1, pixels_per_cell);
  cv::Mat image(dod.rows * k + 40, dod.cols * k, CV_8UC3, cv::Scalar(255, 255, 255));
  double scale = 0.0;
  for (int r = 0; r < dod.rows; ++r)
    for (int c = 0; c < dod.cols; ++c)
      if (change.change_class.at(r, c) != kBelowDetection && !Raster::IsNoData(dod.at(r, c)))
        scale = std::max(scale, std::abs(static_cast<double>(dod.at(r, c))));
  const cv::Mat shade = shade_dem ? ComputeHillshade(*shade_dem) : cv::Mat();
  for (int r = 0; r < dod.rows; ++r)
    for (int c = 0; c < dod.cols; ++c) {
      const float dz = dod.at(r, c);
      if (Raster::IsNoData(dz)) continue;
      cv::Vec3b colour;
      if (change.change_class.at(r, c) != kBelowDetection) {
        // Even the smallest significant change is visibly coloured.
        colour = Diverging((dz < 0 ? -1 : 1) * (0.25 + 0.75 * std::abs(dz) / scale));
      } else {
        const float s = shade.empty() ? NAN : shade.at<float>(r, c);
        const uint8_t grey = cv::saturate_cast<uint8_t>(std::isfinite(s) ? 120 + 110 * s : 200);
        colour = cv::Vec3b(grey, grey, grey);
      }
      image(cv::Rect(c * k, r * k, k, k)).setTo(colour);
    }
  for (const SubsidenceRegion& region : change.regions) {
    for (const OutlinePolygon& polygon : region.outline) {
      std::vector<cv::Point> points;
      for (const Eigen::Vector2d& p : polygon.exterior) points.push_back(ToPixel(dod, k, p));
      cv::polylines(image, points, true, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    cv::putText(image, std::to_string(region.id), ToPixel(dod, k, region.centroid_xy_m),
                cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  if (station_xy_m) DrawStationMarker(&image, dod, k, *station_xy_m);
  char text[200];
  if (scale > 0.0)
    std::snprintf(text, sizeof text, "red lowering, blue raising (full at %.2f m); grey < LoD",
                  scale);
  else
    std::snprintf(text, sizeof text, "no significant change (grey < LoD)");
  DrawScaleBarAndText(&image, dod, k, dod.rows * k + 12, text);
  return image;
}

}  // namespace ts
