#pragma once
// The stage's dual-axis inclinometer rides the pan platform (DESIGN.md, the stage's device
// block), so it turns with the pan. At encoder pan p it reads the platform's tilt about its own
// X and Y axes, in the convention of StageKinematics' levelling (at true pan 0 a perfect
// inclinometer reads levelling_x_deg, levelling_y_deg), plus its index error: the reading of a
// level platform, a property of the instrument that drifts with temperature and handling.
//
// One reading cannot tell the levelling from the index error. Readings at pans round the
// circle can: the levelling turns with the pan, the index error does not. This is the reversal
// a theodolite's two faces make for its compensator; with the 12 pans of a panorama the
// levelling is known to the reading noise over sqrt(6), not to the index error.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "processing/geometry/stage_kinematics.h"

namespace ts {

struct InclinometerReading {
  double pan_deg = 0.0;                                // the encoder's pan when it was read
  Eigen::Vector2d tilt_deg = Eigen::Vector2d::Zero();  // x, y
};

// What the inclinometer reads at encoder pan `pan_deg` on a stage levelled as `stage` (its
// levelling and pan zero), with index error `index_error_deg`. Exact, not small-angle.
Eigen::Vector2d InclinometerReads(const StageKinematics& stage, double pan_deg,
                                  const Eigen::Vector2d& index_error_deg);

struct LevellingFit {
  Eigen::Vector2d levelling_deg = Eigen::Vector2d::Zero();
  Eigen::Vector2d index_error_deg = Eigen::Vector2d::Zero();
  double levelling_sigma_deg = 0.0;  // per axis, the larger of the two
};

// The levelling and the index error from readings at several pans (least squares, the model
// above, the stage's pan zero as given), each reading with sigma `reading_sigma_deg`; the
// levelling's sigma from that sigma or from the residuals, whichever is larger. None when the
// pans do not separate the two (fewer than 3 readings, or all within 60 deg of one another).
std::optional<LevellingFit> FitLevelling(const std::vector<InclinometerReading>& readings,
                                         const StageKinematics& stage, double reading_sigma_deg);

}  // namespace ts
