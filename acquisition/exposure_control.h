#pragma once
// Exposure control for a stereo pair: both cameras share one exposure (so left and right
// images of the same ground look alike); a pair that is too dark or too clipped is retaken
// with a corrected exposure. Judged on the lower two thirds of the images, which look at
// the ground: a bright sky at the top must not darken the terrain.
#include <opencv2/core.hpp>
#include <string>

#include "core/options.h"

namespace ts {

struct ExposureOptions {
  double target_mean = 0.35;  // of full scale, for the ground
  double min_mean = 0.12;     // below: retake brighter
  double max_mean = 0.75;     // above: retake darker
  double max_clipped = 0.02;  // fraction of saturated pixels that triggers a retake
  double min_exposure_us = 20.0;
  double max_exposure_us = 500000.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("target_mean", self.target_mean, {"mean grey of the ground, of full scale", "", 0.01, 0.99});
    v("min_mean", self.min_mean, {"darker: retaken brighter", "", 0, 1});
    v("max_mean", self.max_mean, {"brighter: retaken darker", "", 0, 1});
    v("max_clipped", self.max_clipped, {"share of saturated pixels that retakes", "", 1e-6, 1});
    v("min_exposure_us", self.min_exposure_us, {"shortest exposure", "us", 1, 10000000});
    v("max_exposure_us", self.max_exposure_us, {"longest exposure", "us", 1, 10000000});
  }
  bool Check(std::string* why) const;
};

struct ExposureVerdict {
  bool ok = true;
  double mean = 0.0;     // fraction of full scale (both images)
  double clipped = 0.0;  // fraction of saturated pixels (both images)
  double next_exposure_us = 0.0;
  std::string reason;  // why a retake, empty if ok
};

ExposureVerdict JudgeExposure(const cv::Mat& left, const cv::Mat& right, double exposure_us,
                              const ExposureOptions& options);

}  // namespace ts
