#include "processing/calibration/circular_target.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "processing/matching/lsm.h"

namespace ts {
namespace {

// An ideal disc of the radius, centred on the template's centre pixel, anti-aliased.
cv::Mat DiscTemplate(double radius_px, int half) {
  constexpr int kSamples = 8;
  cv::Mat t(2 * half + 1, 2 * half + 1, CV_32FC1);
  for (int y = 0; y < t.rows; ++y)
    for (int x = 0; x < t.cols; ++x) {
      int inside = 0;
      for (int j = 0; j < kSamples; ++j)
        for (int i = 0; i < kSamples; ++i) {
          const double dx = x - half - 0.5 + (i + 0.5) / kSamples;
          const double dy = y - half - 0.5 + (j + 0.5) / kSamples;
          inside += dx * dx + dy * dy <= radius_px * radius_px;
        }
      t.at<float>(y, x) = static_cast<float>(inside) / (kSamples * kSamples);
    }
  return t;
}

struct Blob {
  Eigen::Vector2d centroid;
  double distance;
};

// The bright components of the window that may be the disc, each by its weighted centroid.
std::vector<Blob> DiscCandidates(const cv::Mat& window, const cv::Point& origin,
                                 const Eigen::Vector2d& predicted, double radius_px,
                                 double search_radius_px) {
  double low = 0.0, high = 0.0;
  cv::minMaxLoc(window, &low, &high);
  const float threshold = static_cast<float>(0.5 * (low + high));
  const cv::Mat mask = window > threshold;
  cv::Mat labels, stats, centres;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centres, 8, CV_32S);
  const double area = M_PI * radius_px * radius_px;
  std::vector<Blob> blobs;
  for (int k = 1; k < n; ++k) {
    const int* s = stats.ptr<int>(k);
    const bool touches = s[cv::CC_STAT_LEFT] == 0 || s[cv::CC_STAT_TOP] == 0 ||
                         s[cv::CC_STAT_LEFT] + s[cv::CC_STAT_WIDTH] == window.cols ||
                         s[cv::CC_STAT_TOP] + s[cv::CC_STAT_HEIGHT] == window.rows;
    if (touches || s[cv::CC_STAT_AREA] < 0.3 * area || s[cv::CC_STAT_AREA] > 3.0 * area) continue;
    double sum = 0.0, sx = 0.0, sy = 0.0;
    for (int y = s[cv::CC_STAT_TOP]; y < s[cv::CC_STAT_TOP] + s[cv::CC_STAT_HEIGHT]; ++y)
      for (int x = s[cv::CC_STAT_LEFT]; x < s[cv::CC_STAT_LEFT] + s[cv::CC_STAT_WIDTH]; ++x) {
        if (labels.at<int>(y, x) != k) continue;
        const double q = window.at<float>(y, x) - threshold;
        sum += q, sx += q * x, sy += q * y;
      }
    const Eigen::Vector2d c(origin.x + sx / sum, origin.y + sy / sum);
    const double d = (c - predicted).norm();
    if (d <= search_radius_px) blobs.push_back({c, d});
  }
  std::sort(blobs.begin(), blobs.end(),
            [](const Blob& a, const Blob& b) { return a.distance < b.distance; });
  return blobs;
}

}  // namespace

TargetMeasurement MeasureCircularTarget(const cv::Mat& image, const Eigen::Vector2d& predicted,
                                        double radius_px, double search_radius_px,
                                        const CircularTargetOptions& o) {
  TargetMeasurement m;
  if (radius_px < o.min_radius_px || radius_px > o.max_radius_px) {
    m.why = "disc radius " + std::to_string(radius_px) + " px outside the measurable range";
    return m;
  }
  const int half_window = static_cast<int>(std::ceil(search_radius_px + 2.5 * radius_px));
  const cv::Rect wanted(static_cast<int>(std::lround(predicted.x())) - half_window,
                        static_cast<int>(std::lround(predicted.y())) - half_window,
                        2 * half_window + 1, 2 * half_window + 1);
  const cv::Rect window = wanted & cv::Rect(0, 0, image.cols, image.rows);
  if (window.area() == 0) {
    m.why = "predicted outside the image";
    return m;
  }
  const std::vector<Blob> blobs =
      DiscCandidates(image(window), window.tl(), predicted, radius_px, search_radius_px);
  if (blobs.empty()) {
    m.why = "no disc of the expected size near the prediction";
    return m;
  }
  if (blobs.size() > 1) {
    m.why = "two discs near the prediction";
    return m;
  }
  m.centroid_px = blobs[0].centroid;
  // The matched window reaches 1.7 radii, inside the dark surround; the template a pixel
  // beyond it (the matching's gradients).
  const int half = std::min(static_cast<int>(std::ceil(1.7 * radius_px)) + 1, 50);
  const cv::Mat disc = DiscTemplate(radius_px, half + 2);
  LsmOptions lsm;
  lsm.half_window_px = half;
  lsm.max_iterations = 50;  // the disc's ellipse takes more than a texture's shift
  lsm.max_shift_px = std::max(1.0, 0.5 * radius_px);
  lsm.min_correlation = o.min_correlation;
  lsm.max_sigma_px = o.max_sigma_px;
  const LsmResult r = MatchLsm(disc, ComputeGradients(disc), cv::Point(half + 2, half + 2), image,
                               m.centroid_px, lsm);
  if (!r.ok) {
    m.why = "least-squares matching: " + r.why;
    return m;
  }
  m.ok = true;
  m.pixel = r.position_px;
  m.sigma_px = std::max(r.sigma_x_px, r.sigma_y_px);
  return m;
}

}  // namespace ts
