#pragma once
// An adjusted stage (issue 21) against the simulator's truth, for tests and benchmarks: the
// cameras' placement errors, and the truth as the estimate's held parameters see it.
#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

#include "core/stage_pose.h"
#include "processing/calibration/rig_adjustment.h"
#include "processing/geometry/rotation.h"

namespace ts::testing {

struct CameraErrors {
  double deg = 0.0, m = 0.0;  // the largest over the cameras
};

inline double AngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return DegFromRad(Eigen::AngleAxisd(a.transpose() * b).angle());
}

// Each camera's pose in a control field's frame over a session's poses: the truth's at the
// true angles against the estimate's at the read-back ones, placed by the adjusted field pose.
inline CameraErrors FieldPlacementErrors(const Calibration& truth,
                                         const Eigen::Isometry3d& field_from_station,
                                         const std::vector<StagePose>& true_poses,
                                         const Calibration& estimate,
                                         const Eigen::Isometry3d& l_from_field,
                                         const std::vector<RigPose>& read_poses) {
  CameraErrors e;
  for (size_t k = 0; k < true_poses.size(); ++k)
    for (Side side : {Side::kLeft, Side::kRight}) {
      const Eigen::Isometry3d t =
          field_from_station *
          truth.LFromCamera(side, true_poses[k].pan_deg, true_poses[k].tilt_deg);
      const Eigen::Isometry3d a =
          l_from_field.inverse() *
          estimate.LFromCamera(side, read_poses[k].pan_deg, read_poses[k].tilt_deg);
      e.deg = std::max(e.deg, AngleDeg(t.linear(), a.linear()));
      e.m = std::max(e.m, (t.translation() - a.translation()).norm());
    }
  return e;
}

inline bool IsStageOffset(int i) { return (i >= 4 && i <= 6) || (i >= 8 && i <= 10); }

// The truth as the estimate's rig frame and held parameters see it. Two calibrations lay the
// rig frame S on the same cameras each its own way (X along its own baseline, Y near the
// previous rig's: StereoRig::FromStereoCalibration, CalibrationOf), so the same cameras on the
// same plate have rig rotations that differ by how the two S lie on them: the truth's rotation
// is taken into the S of the cameras the adjustment used. Then the tilt zero and the rig's
// omega turn the views about one axis, so with one of them held at another value than the
// truth the same cameras have the other shifted alike and the rig's offset turned with them;
// the tilt axis's and the rig's x offsets both lie along the tilt axis (to the skew's cosine).
inline StageVector TruthInTheEstimatesGauge(const Calibration& truth_calibration,
                                            const RigAdjustment& r) {
  constexpr int kTiltZero = 3, kTiltAxisX = 4, kRigX = 8, kRigOmega = 11;
  StageVector t = StageVectorOf(truth_calibration.stage);
  const Eigen::Matrix3d tilted_from_left =
      RotationFromOpkDeg(truth_calibration.stage.rig_rotation_opk_deg) *
      truth_calibration.rig.S_from_left;
  const Eigen::Vector3d rig_rotation =
      OpkDegFromRotation(tilted_from_left * r.cameras.rig.S_from_left.transpose());
  for (int k = 0; k < 3; ++k) t[kRigOmega + k] = rig_rotation[k];
  const StageVector e = StageVectorOf(r.stage);
  const double turn = r.sigma[kRigOmega] == 0.0   ? e[kRigOmega] - t[kRigOmega]
                      : r.sigma[kTiltZero] == 0.0 ? e[kTiltZero] - t[kTiltZero]
                                                  : 0.0;
  t[kTiltZero] += turn;
  t[kRigOmega] += turn;
  const Eigen::Vector3d offset =
      RotationX(RadFromDeg(turn)) * Eigen::Vector3d(t[kRigX], t[kRigX + 1], t[kRigX + 2]);
  for (int k = 0; k < 3; ++k) t[kRigX + k] = offset[k];
  const double along = r.sigma[kRigX] == 0.0        ? e[kRigX] - t[kRigX]
                       : r.sigma[kTiltAxisX] == 0.0 ? e[kTiltAxisX] - t[kTiltAxisX]
                                                    : 0.0;
  t[kRigX] += along;
  t[kTiltAxisX] -= along;
  return t;
}

}  // namespace ts::testing
