#pragma once
// Is the calibration good enough? What a calibration determines is where a point appears: for
// one camera, the projection of a direction (up to a rotation of the camera, which its pose
// takes up); for the stereo pair, where a point that the left camera sees at pixel u, d metres
// away, appears in the right image: the correspondence every stereo match and every DEM point
// stands on. Over a grid of the frame, at 10 m and 30 m:
//   - the predicted uncertainty of that map, from the adjustment's joint covariance;
//   - split-half validation: the views divided into two halves (alternate placements), each
//     calibrated alone; their maps differ, and the difference is compared with the sigma the
//     two halves predict for it (about 1 when the model describes the lens, far above when it
//     follows the noise, a board that is not flat, or blurred views);
// and a verdict in plain words with its reason: good, needs views at the edges (the
// uncertainty is large where the frame has no observations), needs more views, overfitted.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/options.h"
#include "processing/calibration/camera_calibration.h"

namespace ts {

struct ValidationOptions {
  double near_m = 10.0;
  double far_m = 30.0;
  int grid_columns = 16;
  int grid_rows = 12;
  // A map known to a tenth of a pixel everywhere: small against the matching's third of one
  // (seed 003, sigma_p).
  double good_uncertainty_px = 0.1;
  // The halves' difference over its predicted sigma (RMS over the grid) above which the model
  // is said to follow something other than the lens.
  double max_consistency = 3.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("near_m", self.near_m, {"nearer distance validated", "m", 0.1, 1e4});
    v("far_m", self.far_m, {"farther distance validated", "m", 0.1, 1e4});
    v("grid_columns", self.grid_columns, {"grid over the frame, columns", "", 2, 200});
    v("grid_rows", self.grid_rows, {"grid over the frame, rows", "", 2, 200});
    v("good_uncertainty_px", self.good_uncertainty_px,
      {"a calibration is good when its map is known this well everywhere", "px", 1e-3, 10});
    v("max_consistency", self.max_consistency,
      {"halves differing by more of their sigmas: overfitted", "", 1, 100});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

struct MapValidation {
  double distance_m = 0.0;  // 0: a single camera's directions
  // Per grid point, the larger axis of its ellipse; NaN where the right camera does not see
  // the point.
  std::vector<double> sigma_px;
  double max_sigma_px = 0.0, median_sigma_px = 0.0;
  bool split = false;                 // the halves compared
  std::vector<double> difference_px;  // per grid point, between the halves
  double max_difference_px = 0.0;
  double consistency = 0.0;  // RMS over the grid of difference / its predicted sigma
};

struct CalibrationValidation {
  int columns = 0, rows = 0;
  // The pixels validated (the left camera's): the centres of the grid's cells, row-major.
  std::vector<Eigen::Vector2d> grid;
  std::vector<MapValidation> maps;  // one per distance (one for a single camera)
  std::string split_note;           // why the halves were not compared, when they were not
  std::string verdict;              // good | needs views at the edges | needs more views |
                                    // overfitted
  std::string reason;
};

// The stereo pair, and the halves when the views allow (each half calibrated with `options`).
CalibrationValidation ValidateStereo(const StereoCalibration& full, const TargetViews& left,
                                     const TargetViews& right,
                                     const CameraCalibrationOptions& options,
                                     const ValidationOptions& validation);
// One camera: directions, up to the camera's rotation.
CalibrationValidation ValidateCamera(const CameraCalibration& full, const TargetViews& views,
                                     const CameraCalibrationOptions& options,
                                     const ValidationOptions& validation);

}  // namespace ts
