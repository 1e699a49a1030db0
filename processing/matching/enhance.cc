#include "processing/matching/enhance.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ts {

bool EnhanceOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (!wallis || wallis_window_px % 2 == 1) return true;
  if (why) *why = "wallis_window_px must be odd";
  return false;
}

cv::Mat Enhance(const cv::Mat& image, const EnhanceOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("enhance: " + why);
  cv::Mat g;
  image.convertTo(g, CV_32F);
  if (o.gaussian_sigma_px > 0.0) cv::GaussianBlur(g, g, {0, 0}, o.gaussian_sigma_px);
  if (!o.wallis) return g;
  const cv::Size window(o.wallis_window_px, o.wallis_window_px);
  cv::Mat mean, mean_sq;
  cv::boxFilter(g, mean, CV_32F, window, {-1, -1}, true, cv::BORDER_REFLECT);
  cv::boxFilter(g.mul(g), mean_sq, CV_32F, window, {-1, -1}, true, cv::BORDER_REFLECT);
  cv::Mat variance = mean_sq - mean.mul(mean);
  cv::max(variance, 0.0, variance);
  cv::Mat deviation;
  cv::sqrt(variance, deviation);
  const float c = static_cast<float>(o.contrast), b = static_cast<float>(o.brightness);
  const float st = static_cast<float>(o.target_deviation), mt = static_cast<float>(o.target_mean);
  cv::Mat out(g.size(), CV_32FC1);
  for (int y = 0; y < g.rows; ++y) {
    const float* gv = g.ptr<float>(y);
    const float* m = mean.ptr<float>(y);
    const float* s = deviation.ptr<float>(y);
    float* d = out.ptr<float>(y);
    for (int x = 0; x < g.cols; ++x) {
      // A flat window (s = 0) keeps its mean: no noise is blown up to full contrast.
      const float gain = c * st / (c * s[x] + (1.0f - c) * st + 1e-6f);
      d[x] = (gv[x] - m[x]) * gain + b * mt + (1.0f - b) * m[x];
    }
  }
  return out;
}

}  // namespace ts
