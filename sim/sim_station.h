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
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("scene", self.scene, {"built-in scene, unless dem_file is set"});
    v("dem_file", self.dem_file, {"GeoTIFF DEM as terrain instead of a scene"});
    v("seed", self.seed, {"scene and rig seed", "", 0, 1.8e19});
    v("stage_height_m", self.stage_height_m, {"stage centre above the station mark", "m", 0.3, 5});
    v("epoch", self.epoch,
      {"survey epoch of the same site (later epochs get new sensor noise)", "", 1, 1000000});
  }
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
  int view = 0;  // of calibration targets shown at the pose (a board moved): its own noise
};
// range_m, if given, receives the true distance (m) from the projection centre to the surface
// at each pixel centre (CV_32FC1, NaN for sky).
cv::Mat RenderFrame(Renderer& renderer, const SimStation& station, const FrameRequest& request,
                    cv::Mat* range_m = nullptr);
// The two halves of RenderFrame: the scene's radiance seen at the pose (the costly part,
// independent of exposure, gain and format), and the sensor's exposure of it.
cv::Mat RenderRadiance(Renderer& renderer, const SimStation& station, const FrameRequest& request,
                       cv::Mat* range_m = nullptr);
cv::Mat ExposeFrame(const SimStation& station, const FrameRequest& request,
                    const cv::Mat& radiance);

struct StationRenderOptions {
  double exposure_us = kDefaultExposureUs;
  double gain_db = 0.0;
  PixelFormat format = PixelFormat::kMono8;
  RenderOptions render;
  CapturePlanOptions plan;
  double encoder_noise_deg = 0.002;  // where the axes really stop around the commanded angle
  bool write_range_images = false;   // truth/range/pair_NN_{left,right}.tif, float32 metres
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("exposure_us", self.exposure_us, {"exposure", "us", 1, 1e7});
    v("gain_db", self.gain_db, {"gain", "dB", 0, 48});
    v("format", self.format, {"pixel format (0 Mono8, 1 Mono16)"});
    v("encoder_noise_deg", self.encoder_noise_deg,
      {"where the axes stop around the commanded angle (sigma)", "deg", 0, 0.999});
    v("write_range_images", self.write_range_images,
      {"also write the true range image of every view into the truth directory"});
    v.Group("render", self.render);
    v.Group("plan", self.plan);
  }
  bool Check(std::string* why) const;
};

// Writes a complete station directory straight from the renderer (no hardware path) and the
// truth directory; truth.json also lists the true (unrounded) encoder angles of every pair.
// progress(done, total) is called after each pair.
Status RenderStationDirectory(const SimStation& station, const StationRenderOptions& options,
                              const std::string& station_dir, const std::string& truth_dir,
                              const std::function<void(int, int)>& progress = {});

}  // namespace ts::sim
