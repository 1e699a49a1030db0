#pragma once
// panorama.png: the left images of a station mosaicked on a cylinder around the station's
// vertical axis, each placed by its pair's stage angles through the calibration: column =
// azimuth from the pan-zero direction, clockwise; row = elevation. Every panorama pixel takes
// the left image whose optical axis is closest to its direction.
#include <opencv2/core.hpp>
#include <vector>

#include "core/options.h"
#include "processing/geometry/calibration.h"
#include "processing/matching/station_matching.h"

namespace ts {

struct PanoramaOptions {
  double deg_per_px = 0.2;  // 1800 px around: an overview (the raw images hold the detail)
  double min_elevation_deg = -60.0;
  double max_elevation_deg = 50.0;  // upper poses (capture_plan.h) reach 32 + 15.5 deg
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("deg_per_px", self.deg_per_px, {"panorama resolution", "deg", 0.01, 10});
    v("min_elevation_deg", self.min_elevation_deg, {"lowest elevation shown", "deg", -90, 90});
    v("max_elevation_deg", self.max_elevation_deg, {"highest elevation shown", "deg", -90, 90});
  }
  bool Check(std::string* why) const;
};

// The panorama built pair by pair (an incremental station adds each pair as it is matched):
// every pixel keeps the image whose axis is closest to its direction among those added so far.
class PanoramaBuilder {
 public:
  PanoramaBuilder(const Calibration& calibration, const PanoramaOptions& options);
  // Their left images, in one pass over the panorama (each pixel projected once).
  void Add(const std::vector<StereoPairImages>& pairs);
  // 8-bit grey, cropped to the rows some image sees; black where no image sees.
  cv::Mat Image() const;

 private:
  Calibration calibration_;
  PanoramaOptions options_;
  cv::Mat pano_;      // CV_8UC1
  cv::Mat best_dot_;  // CV_64FC1: cosine between the pixel's direction and its image's axis
};

// The largest angle (deg) by which `to` turns a left camera's view from where `from` put it, over
// the pairs' stage angles: how far a panorama drawn on `from` stands from one drawn on `to`.
double LargestViewTurnDeg(const Calibration& from, const Calibration& to,
                          const std::vector<StereoPairImages>& pairs);

// All pairs at once: a PanoramaBuilder given each pair in order.
cv::Mat RenderPanorama(const Calibration& calibration, const std::vector<StereoPairImages>& pairs,
                       const PanoramaOptions& options = {});

}  // namespace ts
