#pragma once
// panorama.png: the left images of a station mosaicked on a cylinder around the station's
// vertical axis, each placed by its pair's stage angles through the calibration: column =
// azimuth from the pan-zero direction, clockwise; row = elevation. Every panorama pixel takes
// the left image whose optical axis is closest to its direction.
#include <opencv2/core.hpp>
#include <vector>

#include "processing/geometry/calibration.h"
#include "processing/matching/station_matching.h"

namespace ts {

struct PanoramaOptions {
  double deg_per_px = 0.2;  // 1800 px around: an overview (the raw images hold the detail)
  double min_elevation_deg = -60.0;
  double max_elevation_deg = 50.0;  // upper poses (capture_plan.h) reach 32 + 15.5 deg
};

// 8-bit grey, cropped to the rows some image sees; black where no image sees.
cv::Mat RenderPanorama(const Calibration& calibration, const std::vector<StereoPairImages>& pairs,
                       const PanoramaOptions& options = {});

}  // namespace ts
