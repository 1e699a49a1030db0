#pragma once
// Calibration targets served by the simulated cameras instead of the scene (`sim serve
// --calibration chessboard|charuco|field`), for `capture --calibration` over the real drivers:
//   a board   the placements of a board session (calibration_views.h), one per pair: the
//             camera's n-th frame shows placement n (the helper moves the board after each
//             pair; both cameras are triggered for every pair, so they stay together);
//   a field   the control field of a field session (calibration_field.h), seen at whatever
//             pose the stage is in.
// The truth directory holds the true rig (calibration.yaml) either way; for a field it gains
// what the team is given: field.yaml (surveyed), and marks.yaml, the hand marks of the poses
// of the default grid (capture --calibration field), named as the capture names its images.
#include <string>

#include "core/options.h"
#include "core/result.h"
#include "sim/calibration_field.h"
#include "sim/calibration_views.h"
#include "sim/simulated_camera.h"

namespace ts::sim {

struct ServedCalibration {
  std::string kind;  // empty (the scene) | chessboard | charuco | field
  BoardSessionOptions board;
  FieldSessionOptions field;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v.Group("board", self.board);
    v.Group("field", self.field);
  }
};

// Sets both cameras' target_radiance (and target_views); nothing for the scene.
void ServeCalibrationTargets(const SimRig& rig, uint64_t seed, const ServedCalibration& served,
                             SimulatedCameraOptions* left, SimulatedCameraOptions* right);

// A field's files for the team, into truth_dir (nothing for a board or the scene).
Status WriteServedCalibrationTruth(const SimRig& rig, uint64_t seed,
                                   const ServedCalibration& served, const std::string& truth_dir);

}  // namespace ts::sim
