#pragma once
// The simulated rig: the paper's cameras (1392 x 1040 px of 6.45 um, 12 mm, 0.5 m base) on a
// stage, deliberately imperfect. `truth` is how the rig really is (lens distortion, mount
// offsets, encoder zeros, levelling error); `nominal` is what the station knows before
// calibration: the design values, the levelling as the inclinometer reports it, and the
// stage height as measured with a tape. Deterministic for a seed.
#include <cstdint>

#include "processing/geometry/calibration.h"
#include "sim/sensor.h"

namespace ts::sim {

struct SimRig {
  Calibration truth;
  Calibration nominal;
  SensorModel left_sensor;
  SensorModel right_sensor;  // a slightly different sensitivity and black level
  // The inclinometer riding the pan (inclinometer.h): its index error, its noise per reading,
  // and what it reads at the stage's home (encoder pan 0), which a station takes as its
  // levelling until readings round the circle tell the levelling from the index error.
  Eigen::Vector2d inclinometer_index_error_deg = Eigen::Vector2d::Zero();
  double inclinometer_noise_deg = 0.002;
  double inclinometer_x_deg = 0.0;
  double inclinometer_y_deg = 0.0;

  const SensorModel& sensor(Side side) const {
    return side == Side::kLeft ? left_sensor : right_sensor;
  }
};

SimRig MakeSimRig(uint64_t seed, double stage_height_m);
// The tripod bumped after the rig's calibration (issue 21): the tilt encoder's zero and the
// levelling about L's X shift; the inclinometer sees the new levelling, nothing sees the zero.
void BumpTripod(SimRig* rig, double tilt_zero_deg, double levelling_x_deg);
// What the inclinometer reads at encoder pan `pan_deg` (noise aside).
Eigen::Vector2d InclinometerReadsAt(const SimRig& rig, double pan_deg);
// The design calibration of the simulated rig (what `nominal` starts from).
Calibration DesignCalibration(double stage_height_m);

}  // namespace ts::sim
