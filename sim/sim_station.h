#pragma once
// A whole simulated station: scene, its mesh and the simulated rig, built once and shared
// (read-only) by `sim render`, the simulated cameras of `sim serve`, and the tests.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/exposure.h"
#include "core/result.h"
#include "processing/geometry/capture_plan.h"
#include "processing/io/image_file.h"
#include "sim/renderer.h"
#include "sim/scene.h"
#include "sim/scene_mesh.h"
#include "sim/sim_rig.h"

namespace ts::sim {

struct SimStationOptions {
  std::string scene = "hills";  // a built-in scene, unless dem_file is set
  std::string dem_file;         // any GeoTIFF DEM as terrain
  uint64_t seed = 1;
  double stage_height_m = 1.5;
  // A later epoch of the same site (same ground texture and rig, new sensor noise), where the
  // ground may have sunk in bowls and the sun may stand elsewhere.
  int epoch = 1;
  std::vector<Subsidence> subsidence;
  std::vector<double> sun_deg;  // empty: the scene's sun; else {azimuth, elevation}
  bool Check(std::string* why) const;
};

struct SimStation {
  Scene scene;
  SceneMesh mesh;
  SimRig rig;
};

Result<std::shared_ptr<const SimStation>> BuildSimStation(const SimStationOptions& options);

// One camera frame as the simulated sensor delivers it, for the stage at the given encoder
// readings. The noise is seeded by scene, side and pose, so the same request gives the same
// image (the offline render and the simulated GigE camera agree pixel for pixel).
struct FrameRequest {
  Side side = Side::kLeft;
  double pan_deg = 0.0;  // encoder readings
  double tilt_deg = 0.0;
  double exposure_us = kDefaultExposureUs;
  double gain_db = 0.0;
  PixelFormat format = PixelFormat::kMono8;
  RenderOptions render;
};
// range_m, if given, receives the true distance (m) from the projection centre to the surface
// at each pixel centre (CV_32FC1, NaN for sky).
cv::Mat RenderFrame(Renderer& renderer, const SimStation& station, const FrameRequest& request,
                    cv::Mat* range_m = nullptr);

struct StationRenderOptions {
  double exposure_us = kDefaultExposureUs;
  double gain_db = 0.0;
  PixelFormat format = PixelFormat::kMono8;
  RenderOptions render;
  CapturePlanOptions plan;
  double encoder_noise_deg = 0.002;  // where the axes really stop around the commanded angle
  bool write_range_images = false;   // truth/range/pair_NN_{left,right}.tif, float32 metres
  bool Check(std::string* why) const;
};

// Writes a complete station directory straight from the renderer (no hardware path) and the
// truth directory; truth.json also lists the true (unrounded) encoder angles of every pair.
// progress(done, total) is called after each pair.
Status RenderStationDirectory(const SimStation& station, const StationRenderOptions& options,
                              const std::string& station_dir, const std::string& truth_dir,
                              const std::function<void(int, int)>& progress = {});

}  // namespace ts::sim
