#include "acquisition/exposure_control.h"

#include <algorithm>
#include <cmath>

namespace ts {

bool ExposureOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (0.0 < min_mean && min_mean < target_mean && target_mean < max_mean && max_mean < 1.0 &&
      max_clipped > 0.0 && 0.0 < min_exposure_us && min_exposure_us < max_exposure_us)
    return true;
  if (why)
    *why = "need 0 < min_mean < target_mean < max_mean < 1 and min_exposure_us < max_exposure_us";
  return false;
}

namespace {
void Measure(const cv::Mat& image, double* sum, double* clipped, double* count) {
  const double full = image.depth() == CV_16U ? 65535.0 : 255.0;
  const cv::Mat ground = image.rowRange(image.rows / 3, image.rows);
  *sum += cv::sum(ground)[0] / full;
  cv::Mat saturated;
  cv::compare(ground, full, saturated, cv::CMP_GE);
  *clipped += cv::countNonZero(saturated);
  *count += static_cast<double>(ground.total());
}
}  // namespace

ExposureVerdict JudgeExposure(const cv::Mat& left, const cv::Mat& right, double exposure_us,
                              const ExposureOptions& o) {
  double sum = 0.0, clipped = 0.0, count = 0.0;
  Measure(left, &sum, &clipped, &count);
  Measure(right, &sum, &clipped, &count);
  ExposureVerdict v;
  v.mean = sum / count;
  v.clipped = clipped / count;
  v.next_exposure_us = exposure_us;
  double factor = 1.0;
  if (v.clipped > o.max_clipped) {
    factor = std::min(0.5, o.target_mean / std::max(v.mean, 1e-3));
    v.reason = "clipped";
  } else if (v.mean < o.min_mean || v.mean > o.max_mean) {
    factor = o.target_mean / std::max(v.mean, 1e-3);
    v.reason = v.mean < o.min_mean ? "too dark" : "too bright";
  }
  if (!v.reason.empty()) {
    v.next_exposure_us = std::clamp(exposure_us * std::clamp(factor, 0.1, 8.0), o.min_exposure_us,
                                    o.max_exposure_us);
    // At the limit nothing better can be had: accept rather than retake forever.
    v.ok = v.next_exposure_us == exposure_us;
  }
  return v;
}

}  // namespace ts
