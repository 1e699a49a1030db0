#pragma once
// seams.png: the panorama's seams (rig_seams.h) before and after the rig's adjustment, one
// panel each, over azimuth (0-360 deg, left to right) and elevation. Each tie point is a dot
// where it lies, with its disagreement as a line (magnified so that three times the panel's
// median is 12 pixels: a stage that has moved shows as lines running together along each
// seam, closed seams as short lines pointing anywhere); blue within 2 of its predicted sigma,
// red beyond.
#include <opencv2/core.hpp>

#include "processing/calibration/rig_seams.h"

namespace ts {

cv::Mat RenderSeamsImage(const RigSeams& before, const RigSeams& after);

}  // namespace ts
