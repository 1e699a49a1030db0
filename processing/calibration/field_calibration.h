#pragma once
// Calibration at a control field (seed 003 §3): the rig stands before circular targets
// surveyed in a frame of their own and takes views at several stage poses. In each view a few
// targets are measured by hand (the marks); the view's pose follows by resection with the
// design camera (and the image of the other camera by the design relative orientation), every
// other target is predicted, found near its prediction (circular_target.h) and the adjustment
// (camera_calibration.h) solves for the cameras, the poses and the surveyed points within
// their sigma. Then each target is predicted again with the adjusted cameras, which finds the
// ones at the frame's corners the design camera put too far off, and the adjustment repeated.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/calibration/camera_calibration.h"
#include "processing/calibration/circular_target.h"
#include "processing/io/control_field_file.h"

namespace ts {

struct FieldCalibrationOptions {
  // How far from its prediction a target is sought: first with the design camera (whose
  // missing distortion and the marks' errors put targets this far off), then with the
  // adjusted one.
  double first_search_px = 30.0;
  double refine_search_px = 4.0;
  int min_marks = 4;  // hand-measured targets that orient a view
  // A target seen in fewer images adds little but its own unknowns: reported.
  int min_images_per_target = 2;
  // A surveyed point the adjustment moves by more than this many of its sigmas: reported
  // (a disturbed target, a survey error).
  double moved_k = 4.0;
  CircularTargetOptions target;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("first_search_px", self.first_search_px,
      {"search radius around a target's first prediction", "px", 1, 500});
    v("refine_search_px", self.refine_search_px,
      {"search radius after the first adjustment", "px", 0.5, 100});
    v("min_marks", self.min_marks, {"hand-measured targets that orient a view", "", 4, 100});
    v("min_images_per_target", self.min_images_per_target,
      {"report targets found in fewer images", "", 1, 100});
    v("moved_k", self.moved_k, {"report surveyed points moved by more sigmas", "", 1, 100});
    v.Group("target", self.target);
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

struct FieldImage {
  std::string name;  // the file, for messages
  cv::Mat image;     // CV_32FC1
  std::vector<TargetMark> marks;
};

// One camera's images, or the stereo pair's (images[c][k]: camera c at stage pose k).
struct FieldViews {
  std::vector<std::vector<FieldImage>> images;
  std::vector<CameraIntrinsics> start;                                  // the design cameras
  Eigen::Isometry3d second_from_first = Eigen::Isometry3d::Identity();  // design, stereo only
};

struct FieldReport {
  int targets_found = 0;         // distinct targets measured in some image
  double target_sigma_px = 0.0;  // median of the matching's sigmas
  std::vector<std::string> warnings;
  std::vector<TargetViews> views;  // per camera, as the final adjustment saw them
};

Result<CameraCalibration> CalibrateCameraAtField(const ControlField& field, const FieldViews& views,
                                                 const CameraCalibrationOptions& calibration,
                                                 const FieldCalibrationOptions& options,
                                                 FieldReport* report);
Result<StereoCalibration> CalibrateStereoAtField(const ControlField& field, const FieldViews& views,
                                                 const CameraCalibrationOptions& calibration,
                                                 const FieldCalibrationOptions& options,
                                                 FieldReport* report);

// The targets measured with calibrated cameras (views.start; a stereo pair with its relative
// orientation), for the rig adjustment's control field (issue 21), where the stage poses and
// not the views are adjusted: each stage pose oriented by its marks and every target sought
// within first_search_px of its prediction, then each pose oriented by all the targets found
// in it and every target sought again within refine_search_px. Per camera, the views that
// found six targets or more; their placement is the stage pose's index, their target the
// field about its centroid. Errors name what is missing.
Result<std::vector<TargetViews>> MeasureFieldTargets(const ControlField& field,
                                                     const FieldViews& views,
                                                     const FieldCalibrationOptions& options,
                                                     FieldReport* report);

}  // namespace ts
