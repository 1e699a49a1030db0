#include "station/accuracy_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include <opencv2/imgcodecs.hpp>

#include "processing/io/atomic_file.h"

namespace ts {
namespace {

constexpr int kWidth = 900, kHeight = 560;
constexpr int kLeft = 80, kRight = 30, kTop = 70, kBottom = 60;
const cv::Scalar kInk(30, 30, 30), kGrid(215, 215, 215);

struct Axes {
  double x_max, y_max;
  cv::Point At(double x, double y) const {
    const double px = kLeft + x / x_max * (kWidth - kLeft - kRight);
    const double py = kHeight - kBottom - y / y_max * (kHeight - kTop - kBottom);
    return {static_cast<int>(std::lround(px)), static_cast<int>(std::lround(py))};
  }
};

// A "nice" tick step (1, 2 or 5 times a power of ten) giving about eight ticks.
double TickStep(double span) {
  const double raw = span / 8.0, base = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * base >= raw) return m * base;
  return 10.0 * base;
}

void Text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.5) {
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, kInk, 1, cv::LINE_AA);
}

void DrawAxes(cv::Mat& img, const Axes& axes) {
  char label[32];
  const double xs = TickStep(axes.x_max), ys = TickStep(axes.y_max);
  for (double x = 0; x <= axes.x_max + 1e-9; x += xs) {
    cv::line(img, axes.At(x, 0), axes.At(x, axes.y_max), kGrid);
    std::snprintf(label, sizeof(label), "%g", x);
    Text(img, label, axes.At(x, 0) + cv::Point(-8, 20));
  }
  for (double y = 0; y <= axes.y_max + 1e-9; y += ys) {
    cv::line(img, axes.At(0, y), axes.At(axes.x_max, y), kGrid);
    std::snprintf(label, sizeof(label), "%g", y);
    Text(img, label, axes.At(0, y) + cv::Point(-50, 5));
  }
  cv::rectangle(img, axes.At(0, axes.y_max), axes.At(axes.x_max, 0), kInk);
  Text(img, "range Y (m)", cv::Point(kWidth / 2 - 40, kHeight - 15));
  Text(img, "sigma (m)", cv::Point(kLeft - 60, kTop - 12));
}

}  // namespace

Status WriteAccuracyPlot(const std::vector<AccuracyRow>& rows, const std::string& title,
                         const std::string& png_path) {
  if (rows.empty()) return Error{png_path + ": no rows to plot"};
  double y_max = 0.0;
  for (const AccuracyRow& r : rows)
    y_max = std::max({y_max, r.sigma_x_m, r.sigma_y_m, r.sigma_z_m});
  const Axes axes{rows.back().range_m, y_max * 1.05};
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  DrawAxes(img, axes);
  struct Series {
    const char* name;
    double AccuracyRow::*field;
    cv::Scalar colour;
  };
  const Series series[] = {{"sigma X", &AccuracyRow::sigma_x_m, cv::Scalar(200, 80, 0)},
                           {"sigma Y (range)", &AccuracyRow::sigma_y_m, cv::Scalar(0, 0, 210)},
                           {"sigma Z", &AccuracyRow::sigma_z_m, cv::Scalar(0, 150, 0)}};
  int legend_y = kTop + 20;
  for (const Series& s : series) {
    std::vector<cv::Point> line;
    for (const AccuracyRow& r : rows) line.push_back(axes.At(r.range_m, r.*s.field));
    cv::polylines(img, line, false, s.colour, 2, cv::LINE_AA);
    for (const cv::Point& p : line) cv::circle(img, p, 3, s.colour, cv::FILLED, cv::LINE_AA);
    cv::line(img, {kLeft + 20, legend_y - 5}, {kLeft + 50, legend_y - 5}, s.colour, 2);
    Text(img, s.name, {kLeft + 58, legend_y});
    legend_y += 22;
  }
  Text(img, title, cv::Point(kLeft + 150, 30), 0.6);
  std::vector<uchar> png;
  if (!cv::imencode(".png", img, png)) return Error{png_path + ": PNG encoding failed"};
  return WriteFileAtomically(
      png_path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

}  // namespace ts
