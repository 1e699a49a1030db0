#pragma once
// One stereo pair of a simulated station at the given encoder angles, as the cameras would
// deliver it (5 ms exposure), optionally with the left view's true range image.
#include "processing/matching/station_matching.h"
#include "sim/sim_station.h"

namespace ts::testing {

inline StereoPairImages RenderSimPair(sim::Renderer& renderer, const sim::SimStation& station,
                                      int index, double pan_deg, double tilt_deg,
                                      cv::Mat* left_range_m = nullptr) {
  sim::FrameRequest request;
  request.pan_deg = pan_deg;
  request.tilt_deg = tilt_deg;
  request.exposure_us = 5000;
  StereoPairImages pair{index, pan_deg, tilt_deg, {}, {}};
  pair.left = sim::RenderFrame(renderer, station, request, left_range_m);
  request.side = Side::kRight;
  pair.right = sim::RenderFrame(renderer, station, request);
  return pair;
}

}  // namespace ts::testing
