#include "processing/products/seams_image.h"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace ts {
namespace {

constexpr double kPixelsPerDeg = 4.0;
constexpr double kMinElevationDeg = -45.0, kMaxElevationDeg = 45.0;
constexpr int kMargin = 40;
const cv::Scalar kWhite(255, 255, 255), kInk(40, 40, 40), kGrid(220, 220, 220);
const cv::Scalar kBlue(200, 90, 20), kRed(30, 30, 220);

cv::Point At(const Eigen::Vector2d& azimuth_elevation_deg, int top) {
  const double azimuth = std::fmod(azimuth_elevation_deg.x() + 360.0, 360.0);
  return {kMargin + static_cast<int>(std::lround(azimuth * kPixelsPerDeg)),
          top + static_cast<int>(
                    std::lround((kMaxElevationDeg - azimuth_elevation_deg.y()) * kPixelsPerDeg))};
}

void DrawPanel(cv::Mat* image, const RigSeams& seams, const char* when, double magnify, int top) {
  const int width = static_cast<int>(360 * kPixelsPerDeg);
  const int height = static_cast<int>((kMaxElevationDeg - kMinElevationDeg) * kPixelsPerDeg);
  for (int azimuth = 0; azimuth <= 360; azimuth += 30) {
    const int x = kMargin + static_cast<int>(azimuth * kPixelsPerDeg);
    cv::line(*image, {x, top}, {x, top + height}, kGrid);
    cv::putText(*image, std::to_string(azimuth), {x - 8, top + height + 14},
                cv::FONT_HERSHEY_SIMPLEX, 0.35, kInk, 1, cv::LINE_AA);
  }
  const int horizon = At({0.0, 0.0}, top).y;
  cv::line(*image, {kMargin, horizon}, {kMargin + width, horizon}, kGrid);
  cv::rectangle(*image, {kMargin, top}, {kMargin + width, top + height}, kInk);
  for (const RigSeamTie& t : seams.ties) {
    const cv::Point from = At(t.azimuth_elevation_deg, top);
    const Eigen::Vector2d d = magnify * t.disagreement_px;
    const cv::Point to = from + cv::Point(static_cast<int>(std::lround(d.x())),
                                          static_cast<int>(std::lround(d.y())));
    const cv::Scalar colour = t.ratio <= 2.0 ? kBlue : kRed;
    cv::line(*image, from, to, colour, 1, cv::LINE_AA);
    cv::circle(*image, from, 1, colour, cv::FILLED);
  }
  cv::putText(*image,
              fmt::format("seams {}: {} tie points, {:.1f} % within 2 sigma (blue), median "
                          "{:.2f} px = {:.1f} mm; lines x{:.0f}",
                          when, seams.ties.size(), 100 * seams.within_2_sigma, seams.median_px,
                          seams.median_mm, magnify),
              {kMargin, top - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5, kInk, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat RenderSeamsImage(const RigSeams& before, const RigSeams& after) {
  const int width = static_cast<int>(360 * kPixelsPerDeg) + 2 * kMargin;
  const int panel = static_cast<int>((kMaxElevationDeg - kMinElevationDeg) * kPixelsPerDeg);
  cv::Mat image(2 * panel + 4 * kMargin, width, CV_8UC3, kWhite);
  // In each panel three times the median is 12 pixels of the picture.
  const auto magnify = [](const RigSeams& s) { return 12.0 / std::max(3.0 * s.median_px, 1e-3); };
  DrawPanel(&image, before, "before", magnify(before), kMargin);
  DrawPanel(&image, after, "after", magnify(after), panel + 3 * kMargin);
  return image;
}

}  // namespace ts
