#pragma once
// What the command's PNG plots share: a white canvas with axes, "nice" tick steps, text in
// one ink, and the atomic PNG write.
#include <opencv2/core.hpp>
#include <string>

#include "core/result.h"

namespace ts {

// Plot coordinates (x right, y up, from 0 to the maxima) in a rectangle of the image.
struct PlotAxes {
  cv::Rect area;
  double x_max = 1.0, y_max = 1.0;
  cv::Point At(double x, double y) const;
};

// A "nice" tick step (1, 2 or 5 times a power of ten) giving about eight ticks.
double TickStep(double span);
void DrawText(cv::Mat& image, const std::string& text, cv::Point at, double scale = 0.5);
// Grid lines, tick labels, the frame and the two axis labels.
void DrawAxes(cv::Mat& image, const PlotAxes& axes, const std::string& x_label,
              const std::string& y_label);
Status WritePng(const cv::Mat& image, const std::string& path);

}  // namespace ts
