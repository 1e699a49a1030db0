#include "sim/sensor.h"

#include <algorithm>
#include <cmath>

#include "sim/noise.h"

namespace ts::sim {

bool SensorModel::Check(std::string* why) const {
  std::string err;
  if (!(full_well_e > 0) || !(electrons_per_us > 0) || !(sensitivity > 0))
    err = "full well, electrons per us and sensitivity must be positive";
  else if (!(read_noise_e >= 0) || !(vignetting_strength >= 0) ||
           !(black_level_fraction >= 0 && black_level_fraction < 0.5))
    err = "read noise and vignetting must not be negative, black level in [0, 0.5)";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

cv::Mat ExposeImage(const cv::Mat& radiance, const CameraIntrinsics& camera, const SensorModel& s,
                    double exposure_us, double gain_db, PixelFormat format, uint64_t noise_seed) {
  const double max_dn = format == PixelFormat::kMono8 ? 255.0 : 65535.0;
  const double gain = std::pow(10.0, gain_db / 20.0);
  const double dn_per_e = gain / s.full_well_e * max_dn;
  const double black = s.black_level_fraction * max_dn;
  const double f = camera.principal_distance_px;
  cv::Mat out(radiance.rows, radiance.cols, format == PixelFormat::kMono8 ? CV_8UC1 : CV_16UC1);
  for (int y = 0; y < radiance.rows; ++y) {
    const float* in = radiance.ptr<float>(y);
    const double dy = (y - camera.principal_point_y_px) / f;
    for (int x = 0; x < radiance.cols; ++x) {
      const double dx = (x - camera.principal_point_x_px) / f;
      const double cos2 = 1.0 / (1.0 + dx * dx + dy * dy);
      const double vignetting = std::pow(cos2 * cos2, s.vignetting_strength);
      double electrons = std::max(0.0, static_cast<double>(in[x])) * s.sensitivity *
                         s.electrons_per_us * exposure_us * vignetting;
      if (s.noise) {
        // Standard normal from the sum of four uniforms (Irwin-Hall), per pixel hash.
        const uint64_t h = Hash(noise_seed, x, y);
        double u = 0.0;
        for (int k = 0; k < 4; ++k) u += static_cast<double>((h >> (16 * k)) & 0xFFFF) / 65535.0;
        const double normal = (u - 2.0) * std::sqrt(3.0);
        electrons += normal * std::sqrt(electrons + s.read_noise_e * s.read_noise_e);
      }
      const double dn = std::clamp(std::round(black + electrons * dn_per_e), 0.0, max_dn);
      if (format == PixelFormat::kMono8)
        out.at<uint8_t>(y, x) = static_cast<uint8_t>(dn);
      else
        out.at<uint16_t>(y, x) = static_cast<uint16_t>(dn);
    }
  }
  return out;
}

}  // namespace ts::sim
