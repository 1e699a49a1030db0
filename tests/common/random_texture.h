#pragma once
// Uniform noise blurred by a Gaussian of 1.2 px: texture everywhere, at about the scale of
// camera images, reproducible for a seed.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace ts::testing {

inline cv::Mat RandomTexture(int width, int height, unsigned seed) {
  cv::Mat m(height, width, CV_32FC1);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(m, m, {0, 0}, 1.2);
  return m;
}

}  // namespace ts::testing
