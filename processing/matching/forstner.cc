#include "processing/matching/forstner.h"

#include <Eigen/LU>
#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ts {

bool ForstnerOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (border_px > half_window_px) return true;
  if (why) *why = "border_px must exceed half_window_px";
  return false;
}

namespace {

// Förstner's point: argmin sum over the window of (g . (p - x))^2, i.e. N x = sum g g^T x_i.
Eigen::Vector2d Locate(const cv::Mat& gx, const cv::Mat& gy, int cx, int cy, int h) {
  Eigen::Matrix2d n = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (int y = cy - h; y <= cy + h; ++y) {
    for (int x = cx - h; x <= cx + h; ++x) {
      const double u = gx.at<float>(y, x), v = gy.at<float>(y, x);
      Eigen::Matrix2d ggt;
      ggt << u * u, u * v, u * v, v * v;
      n += ggt;
      b += ggt * Eigen::Vector2d(x, y);
    }
  }
  const Eigen::Vector2d p = n.inverse() * b;
  // Keep the estimate inside the pixel's window; farther means a degenerate window.
  if (!p.allFinite() || (p - Eigen::Vector2d(cx, cy)).cwiseAbs().maxCoeff() > h)
    return Eigen::Vector2d(cx, cy);
  return p;
}

}  // namespace

std::vector<InterestPoint> DetectForstner(const cv::Mat& image, const ForstnerOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("Förstner: " + why);
  cv::Mat f;
  image.convertTo(f, CV_32F);
  cv::Mat gx, gy;
  cv::Scharr(f, gx, CV_32F, 1, 0, 1.0 / 32.0);
  cv::Scharr(f, gy, CV_32F, 0, 1, 1.0 / 32.0);
  const int k = 2 * o.half_window_px + 1;
  cv::Mat nxx, nxy, nyy;
  cv::boxFilter(gx.mul(gx), nxx, CV_32F, {k, k}, {-1, -1}, false);
  cv::boxFilter(gx.mul(gy), nxy, CV_32F, {k, k}, {-1, -1}, false);
  cv::boxFilter(gy.mul(gy), nyy, CV_32F, {k, k}, {-1, -1}, false);
  // w in one pass; q only where a candidate is looked at.
  cv::Mat w(f.size(), CV_32F);
  for (int y = 0; y < f.rows; ++y) {
    const float* a = nxx.ptr<float>(y);
    const float* b = nxy.ptr<float>(y);
    const float* c = nyy.ptr<float>(y);
    float* out = w.ptr<float>(y);
    for (int x = 0; x < f.cols; ++x) out[x] = (a[x] * c[x] - b[x] * b[x]) / (a[x] + c[x] + 1e-12f);
  }
  const auto roundness = [&](int x, int y) {
    const float a = nxx.at<float>(y, x), b = nxy.at<float>(y, x), c = nyy.at<float>(y, x);
    const float trace = a + c + 1e-12f;
    return 4.0f * (a * c - b * b) / (trace * trace);
  };
  // Robust threshold: relative to the median weight of the image interior.
  const cv::Rect interior(o.border_px, o.border_px, std::max(1, f.cols - 2 * o.border_px),
                          std::max(1, f.rows - 2 * o.border_px));
  // (Every 4th pixel of every 4th row: the median of a million pixels needs no more.)
  std::vector<float> values;
  for (int y = interior.y; y < interior.y + interior.height; y += 4)
    for (int x = interior.x; x < interior.x + interior.width; x += 4)
      values.push_back(w.at<float>(y, x));
  if (values.empty()) return {};
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  const float threshold =
      std::max(1e-6f, static_cast<float>(o.min_weight_factor) * values[values.size() / 2]);
  // Local maxima (3 x 3), the strongest per cell, then no two closer than half a cell.
  cv::Mat dilated;
  if (o.local_maxima_only)
    cv::dilate(w, dilated, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
  const bool check_roundness = o.min_roundness > 0.0;
  std::vector<InterestPoint> points;
  for (int cy = o.border_px; cy < f.rows - o.border_px; cy += o.cell_px) {
    for (int cx = o.border_px; cx < f.cols - o.border_px; cx += o.cell_px) {
      int best_x = -1, best_y = -1;
      float best = threshold;
      const int x_end = std::min(cx + o.cell_px, f.cols - o.border_px);
      for (int y = cy; y < std::min(cy + o.cell_px, f.rows - o.border_px); ++y) {
        const float* row = w.ptr<float>(y);
        for (int x = cx; x < x_end; ++x) {
          const float v = row[x];
          if (v >= best && (!o.local_maxima_only || v == dilated.at<float>(y, x)) &&
              (!check_roundness || roundness(x, y) >= o.min_roundness)) {
            best = v;
            best_x = x;
            best_y = y;
          }
        }
      }
      if (best_x < 0) continue;
      const Eigen::Vector2d at = o.subpixel
                                     ? Locate(gx, gy, best_x, best_y, o.locate_half_window_px)
                                     : Eigen::Vector2d(best_x, best_y);
      points.push_back({at, best, roundness(best_x, best_y)});
    }
  }
  // Strongest first; a point is kept unless a kept one lies within half a cell. Kept points
  // are binned in half-cell buckets (a linked list per bucket, in two flat arrays), so only
  // the neighbouring buckets need looking at.
  std::sort(points.begin(), points.end(),
            [](const InterestPoint& a, const InterestPoint& b) { return a.weight > b.weight; });
  const double min_distance = 0.5 * o.cell_px;
  const int bucket_cols = static_cast<int>(f.cols / min_distance) + 2;
  const int bucket_rows = static_cast<int>(f.rows / min_distance) + 2;
  std::vector<int> first(static_cast<size_t>(bucket_cols) * bucket_rows, -1), next;
  std::vector<InterestPoint> spread;
  for (const InterestPoint& p : points) {
    const int bx = static_cast<int>(p.position_px.x() / min_distance) + 1;
    const int by = static_cast<int>(p.position_px.y() / min_distance) + 1;
    bool far = true;
    for (int y = by - 1; y <= by + 1 && far; ++y)
      for (int x = bx - 1; x <= bx + 1 && far; ++x)
        for (int i = first[static_cast<size_t>(y) * bucket_cols + x]; i >= 0 && far; i = next[i])
          far =
              (spread[i].position_px - p.position_px).squaredNorm() >= min_distance * min_distance;
    if (!far) continue;
    int& head = first[static_cast<size_t>(by) * bucket_cols + bx];
    next.push_back(head);
    head = static_cast<int>(spread.size());
    spread.push_back(p);
  }
  return spread;
}

}  // namespace ts
