#pragma once
// A simulated control-field session as calibrate --control-field reads it: each stage pose's
// two images (rendered and exposed as `sim render --calibration field` writes them), the hand
// marks in the left images (the right ones are oriented by the design relative orientation),
// the rig's design cameras to start from.
#include <string>

#include "processing/calibration/field_calibration.h"
#include "sim/calibration_field.h"

namespace ts {

inline cv::Mat AsFloatImage(const cv::Mat& mono8) {
  cv::Mat image;
  mono8.convertTo(image, CV_32FC1, 1.0 / 255.0);
  return image;
}

inline FieldViews SimulatedFieldViews(const sim::SimRig& rig, const sim::FieldSession& s,
                                      uint64_t seed, const sim::FieldSessionOptions& options = {}) {
  FieldViews views;
  views.images.resize(2);
  for (size_t k = 0; k < s.poses.size(); ++k)
    for (Side side : {Side::kLeft, Side::kRight}) {
      FieldImage image{std::string(SideName(side)) + "/" + std::to_string(k + 1), {}, {}};
      image.image =
          AsFloatImage(sim::ExposeFieldView(rig, s, side, static_cast<int>(k), seed, options));
      if (side == Side::kLeft) image.marks = s.marks[k].marks;
      views.images[side == Side::kLeft ? 0 : 1].push_back(std::move(image));
    }
  views.start = {rig.nominal.rig.left, rig.nominal.rig.right};
  views.second_from_first = rig.nominal.rig.RightFromLeftCamera();
  return views;
}

}  // namespace ts
