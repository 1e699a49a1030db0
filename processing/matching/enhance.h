#pragma once
// Radiometric enhancement before matching (seed 003: "radiometric enhancement is conducted
// by Gaussian filter to remove noises and illumination differences"):
//   Gaussian: suppresses sensor noise (sigma in px).
//   Wallis:   local contrast normalisation. Over a window, local mean m and deviation s are
//             pulled towards a target m_t, s_t:
//               g' = (g - m) c s_t / (c s + (1 - c) s_t) + b m_t + (1 - b) m
//             With b = c = 1 a linear change of brightness and contrast (left/right exposure,
//             a shadow edge far from the window) disappears entirely.
#include <opencv2/core.hpp>
#include <string>

#include "core/options.h"

namespace ts {

struct EnhanceOptions {
  double gaussian_sigma_px = 0.7;  // 0 = no Gaussian
  bool wallis = true;
  int wallis_window_px = 31;   // odd
  double target_mean = 127.0;  // grey levels of the output
  double target_deviation = 50.0;
  double brightness = 1.0;  // b in [0, 1]
  double contrast = 0.9;    // c in [0, 1]
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("gaussian_sigma_px", self.gaussian_sigma_px, {"Gaussian blur first (0: none)", "px", 0, 10});
    v("wallis", self.wallis, {"Wallis filter (local contrast)"});
    v("wallis_window_px", self.wallis_window_px, {"Wallis window (odd)", "px", 3, 1001});
    v("target_mean", self.target_mean, {"grey level of the output's mean", "", 0, 255});
    v("target_deviation", self.target_deviation,
      {"grey-level deviation of the output", "", 1e-3, 255});
    v("brightness", self.brightness, {"Wallis b: how far the mean moves to the target", "", 0, 1});
    v("contrast", self.contrast, {"Wallis c: how far the deviation moves to the target", "", 0, 1});
  }
  bool Check(std::string* why) const;
};

// Any single-channel image in; CV_32FC1 out.
cv::Mat Enhance(const cv::Mat& image, const EnhanceOptions& options);

}  // namespace ts
