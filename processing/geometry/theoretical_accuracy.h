#pragma once
// Theoretical mapping accuracy of a stereo bar, seed 003 eq. 1 (Di et al.):
//   sigma_Y = Y^2 / (B f) sigma_p
//   sigma_X = sqrt( (Y^2/(B f))^2 (x/f)^2 sigma_p^2 + (Y/f)^2 sigma_x^2 )
//   sigma_Z = sqrt( (Y^2/(B f))^2 (y/f)^2 sigma_p^2 + (Y/f)^2 sigma_y^2 )
// Y range (m), B baseline (m), f principal distance (px), sigma_p the parallax error (px),
// x, y the image coordinates of the point from the principal point (px), sigma_x, sigma_y
// the image-coordinate errors (px). The paper sets sigma_p = 1/3 px. By default the point
// is taken at the image corner, the worst case in the frame, and sigma_x = sigma_y = sigma_p.
#include <string>
#include <vector>

#include "core/options.h"

namespace ts {

struct TheoreticalAccuracyOptions {
  double sigma_parallax_px = 1.0 / 3.0;  // sigma_p
  double sigma_image_px = 1.0 / 3.0;     // sigma_x = sigma_y
  double image_x_px = 0.0;               // x of the point from the principal point; see header
  double image_y_px = 0.0;               // y of the point from the principal point
  double range_min_m = 5.0;
  double range_max_m = 60.0;
  double range_step_m = 5.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("sigma_parallax_px", self.sigma_parallax_px,
      {"parallax (image measurement) error", "px", 1e-6, 100});
    v("sigma_image_px", self.sigma_image_px, {"image coordinate error", "px", 1e-6, 100});
    v("image_x_px", self.image_x_px, {"x of the point from the principal point", "px", -1e5, 1e5});
    v("image_y_px", self.image_y_px, {"y of the point from the principal point", "px", -1e5, 1e5});
    v("range_min_m", self.range_min_m, {"first range", "m", 1e-3, 1e5});
    v("range_max_m", self.range_max_m, {"last range", "m", 1e-3, 1e5});
    v("range_step_m", self.range_step_m, {"range step", "m", 1e-3, 1e5});
  }
  bool Check(std::string* why) const;
};

struct AccuracyRow {
  double range_m = 0.0;
  double sigma_x_m = 0.0;
  double sigma_y_m = 0.0;
  double sigma_z_m = 0.0;
};

// Rows from range_min_m to range_max_m (inclusive) every range_step_m.
std::vector<AccuracyRow> TheoreticalAccuracy(double baseline_m, double principal_distance_px,
                                             const TheoreticalAccuracyOptions& options);

}  // namespace ts
