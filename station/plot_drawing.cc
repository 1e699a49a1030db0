#include "station/plot_drawing.h"

#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string_view>
#include <vector>

#include "processing/io/atomic_file.h"

namespace ts {
namespace {
const cv::Scalar kInk(30, 30, 30), kGrid(215, 215, 215);
}

cv::Point PlotAxes::At(double x, double y) const {
  const double px = area.x + x / x_max * area.width;
  const double py = area.y + area.height - y / y_max * area.height;
  return {static_cast<int>(std::lround(px)), static_cast<int>(std::lround(py))};
}

double TickStep(double span) {
  const double raw = span / 8.0, base = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * base >= raw) return m * base;
  return 10.0 * base;
}

void DrawText(cv::Mat& image, const std::string& text, cv::Point at, double scale) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, kInk, 1, cv::LINE_AA);
}

void DrawAxes(cv::Mat& image, const PlotAxes& axes, const std::string& x_label,
              const std::string& y_label) {
  char label[32];
  const double xs = TickStep(axes.x_max), ys = TickStep(axes.y_max);
  for (double x = 0; x <= axes.x_max + 1e-9; x += xs) {
    cv::line(image, axes.At(x, 0), axes.At(x, axes.y_max), kGrid);
    std::snprintf(label, sizeof(label), "%g", x);
    DrawText(image, label, axes.At(x, 0) + cv::Point(-8, 20));
  }
  for (double y = 0; y <= axes.y_max + 1e-9; y += ys) {
    cv::line(image, axes.At(0, y), axes.At(axes.x_max, y), kGrid);
    std::snprintf(label, sizeof(label), "%g", y);
    DrawText(image, label, axes.At(0, y) + cv::Point(-50, 5));
  }
  cv::rectangle(image, axes.At(0, axes.y_max), axes.At(axes.x_max, 0), kInk);
  DrawText(image, x_label,
           cv::Point(axes.area.x + axes.area.width / 2 - 40, axes.area.y + axes.area.height + 45));
  DrawText(image, y_label, cv::Point(axes.area.x - 60, axes.area.y - 12));
}

Status WritePng(const cv::Mat& image, const std::string& path) {
  std::vector<uchar> png;
  if (!cv::imencode(".png", image, png)) return Error{path + ": PNG encoding failed"};
  return WriteFileAtomically(
      path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace ts
