#pragma once
// A circular target's centre in an image: a bright disc on a dark surround (at least 1.8
// diameters across), near where the target is predicted. First its grey-value weighted
// centroid (seed 004 eq. 4: the pixels above a threshold halfway between the surround and the
// disc, weighted by how far above it they are), then least-squares matching of an ideal disc
// (lsm.h; its affine warp takes the ellipse the disc projects to) with the match's sigma
// (seed 003 §3). A search that finds no disc, two discs, or a disc of the wrong size names
// the reason.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>

#include "core/options.h"

namespace ts {

struct CircularTargetOptions {
  double min_radius_px = 2.0;  // smaller discs are not measured: too few pixels for LSM
  double max_radius_px = 28.0;
  double min_correlation = 0.8;  // of the fitted disc with the image
  double max_sigma_px = 0.3;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("min_radius_px", self.min_radius_px, {"smallest disc radius measured", "px", 1, 100});
    v("max_radius_px", self.max_radius_px, {"largest disc radius measured", "px", 1, 100});
    v("min_correlation", self.min_correlation, {"of the fitted disc with the image", "", 0, 1});
    v("max_sigma_px", self.max_sigma_px, {"reject less precise centres", "px", 1e-3, 10});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

struct TargetMeasurement {
  bool ok = false;
  std::string why;  // when not ok
  Eigen::Vector2d centroid_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // the LSM centre
  double sigma_px = 0.0;                            // the larger of its two sigmas
};

// image: CV_32FC1. The disc is sought within search_radius_px of `predicted`; radius_px is
// its expected radius (the target's diameter over its distance, in pixels).
TargetMeasurement MeasureCircularTarget(const cv::Mat& image, const Eigen::Vector2d& predicted,
                                        double radius_px, double search_radius_px,
                                        const CircularTargetOptions& options = {});

}  // namespace ts
