#include "sim/sim_rig.h"

#include <random>

#include "processing/geometry/inclinometer.h"
#include "processing/geometry/rotation.h"
#include "sim/noise.h"

namespace ts::sim {
namespace {

// The stage at home reads its inclinometer once: the levelling the station starts from.
void ReadInclinometerAtHome(SimRig* rig) {
  const Eigen::Vector2d home =
      InclinometerReads(rig->truth.stage, 0.0, rig->inclinometer_index_error_deg);
  rig->inclinometer_x_deg = home.x();
  rig->inclinometer_y_deg = home.y();
  rig->nominal.stage.levelling_x_deg = home.x();
  rig->nominal.stage.levelling_y_deg = home.y();
}

}  // namespace

Calibration DesignCalibration(double stage_height_m) {
  Calibration cal;
  CameraIntrinsics c;
  c.width_px = 1392;
  c.height_px = 1040;
  c.pixel_size_um = 6.45;
  c.principal_distance_px = 12.0e3 / 6.45;
  c.principal_point_x_px = 695.5;
  c.principal_point_y_px = 519.5;
  cal.rig.left = cal.rig.right = c;
  cal.rig.baseline_m = 0.5;
  cal.stage.height_above_mark_m = stage_height_m;
  // Design geometry of the stage: tilt axis 12 cm above the pan bearing and 2 cm forward,
  // camera bar 10 cm above the tilt axis.
  cal.stage.tilt_axis_offset_m = {0.0, 0.02, 0.12};
  cal.stage.rig_offset_m = {0.0, 0.0, 0.10};
  return cal;
}

SimRig MakeSimRig(uint64_t seed, double stage_height_m) {
  std::mt19937_64 rng(Hash(seed, 0x519, 0x216));
  std::normal_distribution<double> unit(0.0, 1.0);
  auto n = [&](double sigma) { return sigma * unit(rng); };
  SimRig rig;
  rig.nominal = DesignCalibration(stage_height_m);
  Calibration& t = rig.truth;
  t = rig.nominal;
  for (CameraIntrinsics* c : {&t.rig.left, &t.rig.right}) {
    c->principal_distance_px *= 1.0 + n(0.003);
    c->principal_point_x_px += n(4.0);
    c->principal_point_y_px += n(4.0);
    c->k1 = -0.08 + n(0.01);
    c->k2 = 0.05 + n(0.01);
    c->k3 = n(0.005);
    c->p1 = n(2e-4);
    c->p2 = n(2e-4);
    c->scale_x = n(1e-4);
    c->shear = n(5e-5);
  }
  t.rig.baseline_m += n(0.002);
  t.rig.S_from_left = t.rig.S_from_left * RotationFromOpk({n(0.002), n(0.002), n(0.002)});
  t.rig.left_from_right = RotationFromOpk({n(0.003), n(0.003), n(0.002)});
  StageKinematics& s = t.stage;
  s.levelling_x_deg = n(0.15);
  s.levelling_y_deg = n(0.15);
  s.pan_zero_deg = n(1.0);
  s.tilt_zero_deg = n(0.3);
  s.tilt_axis_offset_m += Eigen::Vector3d(n(0.002), n(0.002), n(0.002));
  s.tilt_axis_skew_deg = n(0.05);
  s.rig_offset_m += Eigen::Vector3d(n(0.003), n(0.003), n(0.003));
  s.rig_rotation_opk_deg = {n(0.1), n(0.1), n(0.1)};
  // The inclinometer's index error is about 0.02 deg; the tape measures to about 5 mm.
  rig.inclinometer_index_error_deg.x() = n(0.02);
  rig.inclinometer_index_error_deg.y() = n(0.02);
  ReadInclinometerAtHome(&rig);
  // The tape reaches the tilt axis (its trunnion mark), not L's origin below it: the station
  // puts the origin the design's tilt-axis height below what was taped.
  // (A simulated stage stands 0.3 m or more above its mark, far above its tilt axis's 0.12 m.)
  static_cast<void>(rig.nominal.stage.SetInstrumentHeight(t.stage.InstrumentHeightM() + n(0.005)));
  rig.right_sensor.sensitivity = 0.92;
  rig.right_sensor.black_level_fraction = 0.02;
  return rig;
}

void BumpTripod(SimRig* rig, double tilt_zero_deg, double levelling_x_deg) {
  rig->truth.stage.tilt_zero_deg += tilt_zero_deg;
  rig->truth.stage.levelling_x_deg += levelling_x_deg;
  ReadInclinometerAtHome(rig);
}

Eigen::Vector2d InclinometerReadsAt(const SimRig& rig, double pan_deg) {
  return InclinometerReads(rig.truth.stage, pan_deg, rig.inclinometer_index_error_deg);
}

}  // namespace ts::sim
