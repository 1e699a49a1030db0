#pragma once
// The simulated sensor: radiance -> electrons -> digital numbers.
//   electrons = radiance * sensitivity * electrons_per_us * exposure_us * vignetting
//   vignetting = cos^4(field angle) ^ vignetting_strength (natural illumination fall-off)
//   noise: shot noise (Poisson, as Gaussian) and read noise; gain (dB) amplifies both
//   DN = black level + electrons * gain / full_well * max DN, clipped; Mono8 or Mono16.
// The noise is a pure function of noise_seed and the pixel, so a frame is reproducible.
#include <cstdint>
#include <opencv2/core.hpp>

#include "processing/geometry/camera_model.h"
#include "processing/io/image_file.h"

namespace ts::sim {

struct SensorModel {
  double full_well_e = 20000.0;
  double read_noise_e = 6.0;
  double electrons_per_us = 4.8;       // per unit radiance at 0 dB (radiance 0.5 at 5 ms: 60 %)
  double sensitivity = 1.0;            // this camera relative to nominal (left/right difference)
  double black_level_fraction = 0.01;  // dark offset as a fraction of full scale
  double vignetting_strength = 1.0;    // 0 = none, 1 = cos^4 law
  bool noise = true;
  bool Check(std::string* why) const;
};

cv::Mat ExposeImage(const cv::Mat& radiance, const CameraIntrinsics& camera,
                    const SensorModel& sensor, double exposure_us, double gain_db,
                    PixelFormat format, uint64_t noise_seed);

}  // namespace ts::sim
