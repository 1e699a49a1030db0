#pragma once
// A small valid station directory for tests: a plan of `poses` pairs of which the first
// `captured` are written (random-texture Mono8 images of 64 x 48 px).
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "processing/io/image_file.h"
#include "processing/io/station_manifest.h"

namespace ts::testing {

inline StationManifest MakeStation(const std::string& dir, int poses, int captured) {
  std::filesystem::create_directories(std::filesystem::path(dir) / "raw");
  StationManifest m;
  m.station_id = "TEST-001";
  m.software_version = "test";
  m.rig_name = "test-rig";
  m.calibration.rig.baseline_m = 0.5;
  for (CameraIntrinsics* c : {&m.calibration.rig.left, &m.calibration.rig.right}) {
    c->width_px = 64;
    c->height_px = 48;
    c->principal_distance_px = 80;
    c->principal_point_x_px = 31.5;
    c->principal_point_y_px = 23.5;
  }
  m.image_width_px = 64;
  m.image_height_px = 48;
  for (int i = 0; i < poses; ++i) m.plan.push_back({30.0 * i, -20.0});
  cv::RNG rng(42);
  for (int i = 0; i < captured; ++i) {
    PairRecord p;
    p.index = i;
    p.commanded = m.plan[i];
    p.readback = {m.plan[i].pan_deg + 0.001, m.plan[i].tilt_deg - 0.002};
    p.exposure_us = 5000;
    p.gain_db = 0;
    p.captured_utc = UtcNowIso8601();
    p.left_timestamp_ns = 1000 + i;
    p.right_timestamp_ns = 1000 + i;
    for (Side side : {Side::kLeft, Side::kRight}) {
      cv::Mat image(48, 64, CV_8UC1);
      rng.fill(image, cv::RNG::UNIFORM, 0, 256);
      ImageRecord& record = side == Side::kLeft ? p.left : p.right;
      record.file = StationManifest::ImageFileName(i, side);
      record.sha256 =
          *WritePngAtomically(image, (std::filesystem::path(dir) / record.file).string());
    }
    m.pairs.push_back(p);
  }
  if (!SaveStationManifest(&m, dir).ok()) throw std::runtime_error("cannot save manifest");
  return m;
}

}  // namespace ts::testing
