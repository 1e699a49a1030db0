#include "station/accuracy_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "station/plot_drawing.h"

namespace ts {
namespace {

constexpr int kWidth = 900, kHeight = 560;
constexpr int kLeft = 80, kRight = 30, kTop = 70, kBottom = 60;

}  // namespace

Status WriteAccuracyPlot(const std::vector<AccuracyRow>& rows, const std::string& title,
                         const std::string& png_path) {
  if (rows.empty()) return Error{png_path + ": no rows to plot"};
  double y_max = 0.0;
  for (const AccuracyRow& r : rows)
    y_max = std::max({y_max, r.sigma_x_m, r.sigma_y_m, r.sigma_z_m});
  const PlotAxes axes{cv::Rect(kLeft, kTop, kWidth - kLeft - kRight, kHeight - kTop - kBottom),
                      rows.back().range_m, y_max * 1.05};
  cv::Mat img(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  DrawAxes(img, axes, "range Y (m)", "sigma (m)");
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
    DrawText(img, s.name, {kLeft + 58, legend_y});
    legend_y += 22;
  }
  DrawText(img, title, cv::Point(kLeft + 150, 30), 0.6);
  return WritePng(img, png_path);
}

}  // namespace ts
