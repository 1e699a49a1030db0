#include "processing/cloud/fill_holes.h"

#include <opencv2/imgproc.hpp>

namespace ts {
namespace {

// weight: 1 known, 0 unknown (fractions on coarser levels). Fills in place.
void PullPush(cv::Mat& value, cv::Mat& weight) {
  if (value.rows <= 1 && value.cols <= 1) return;
  const int rows = (value.rows + 1) / 2, cols = (value.cols + 1) / 2;
  cv::Mat coarse_value(rows, cols, CV_32FC1, cv::Scalar(0));
  cv::Mat coarse_weight(rows, cols, CV_32FC1, cv::Scalar(0));
  for (int r = 0; r < value.rows; ++r)
    for (int c = 0; c < value.cols; ++c) {
      const float w = weight.at<float>(r, c);
      coarse_value.at<float>(r / 2, c / 2) += w * value.at<float>(r, c);
      coarse_weight.at<float>(r / 2, c / 2) += w;
    }
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      float& w = coarse_weight.at<float>(r, c);
      if (w > 0.0f) coarse_value.at<float>(r, c) /= w;
      w = std::min(w, 1.0f);
    }
  if (cv::countNonZero(coarse_weight < 1.0f) > 0) PullPush(coarse_value, coarse_weight);
  // Push: where the fine level is not fully known, blend in the coarse level (bilinear).
  cv::Mat up;
  cv::resize(coarse_value, up, cv::Size(cols * 2, rows * 2), 0, 0, cv::INTER_LINEAR);
  for (int r = 0; r < value.rows; ++r)
    for (int c = 0; c < value.cols; ++c) {
      float& w = weight.at<float>(r, c);
      float& v = value.at<float>(r, c);
      v = w * v + (1.0f - w) * up.at<float>(r, c);
      w = 1.0f;
    }
}

}  // namespace

cv::Mat FillHoles(const cv::Mat& surface, const cv::Mat& known, int relaxation_iterations) {
  CV_Assert(surface.type() == CV_32FC1 && known.type() == CV_8UC1 &&
            surface.size() == known.size());
  cv::Mat value = surface.clone(), weight;
  known.convertTo(weight, CV_32FC1);
  weight.setTo(1.0f, known != 0);
  value.setTo(0.0f, known == 0);
  if (cv::countNonZero(known) == 0) return value;
  PullPush(value, weight);
  // Relax the unknown cells towards the mean of their 4 neighbours (Gauss-Seidel).
  for (int it = 0; it < relaxation_iterations; ++it)
    for (int r = 0; r < value.rows; ++r)
      for (int c = 0; c < value.cols; ++c) {
        if (known.at<uint8_t>(r, c)) continue;
        float sum = 0.0f;
        int n = 0;
        if (r > 0) sum += value.at<float>(r - 1, c), ++n;
        if (r + 1 < value.rows) sum += value.at<float>(r + 1, c), ++n;
        if (c > 0) sum += value.at<float>(r, c - 1), ++n;
        if (c + 1 < value.cols) sum += value.at<float>(r, c + 1), ++n;
        value.at<float>(r, c) = sum / n;
      }
  return value;
}

}  // namespace ts
