#pragma once
// A control field session as a station of the rig adjustment (issue 21): the targets measured
// in its images (field_calibration.h, MeasureFieldTargets) seen from the stage poses the
// session recorded. Each target seen is a point; its start in L is its surveyed position moved
// by the field's pose, which the start calibration and each view's resection give (averaged
// over the poses).
#include <vector>

#include "core/result.h"
#include "processing/calibration/rig_adjustment.h"
#include "processing/calibration/target_views.h"

namespace ts {

// measured: per camera (left, then right), views whose placement indexes `poses` (their
// encoder read-backs).
Result<RigAdjustmentInput> ControlFieldInput(const Calibration& calibration,
                                             const std::vector<TargetViews>& measured,
                                             const std::vector<RigPose>& poses);

}  // namespace ts
