#include "processing/calibration/rig_seams.h"

#include <algorithm>
#include <cmath>

#include "processing/common/median.h"
#include "processing/geometry/camera_model.h"

namespace ts {
namespace {

// How the pixel at which the neighbour (pose `to`) sees the pair's point (`point_in_l`, in the
// L of `calibration`, seen from pose `from`) moves with the two poses' pan and tilt (px per
// degree; the pair's pan and tilt, then the neighbour's): numerically, about `projected`.
Eigen::Matrix<double, 2, 4> SeenAcrossTheAngles(const Calibration& calibration,
                                                const CameraModel& left, const RigPose& from,
                                                const RigPose& to,
                                                const Eigen::Vector3d& point_in_l,
                                                const Eigen::Vector2d& projected) {
  const Eigen::Vector3d in_camera =
      calibration.LFromCamera(Side::kLeft, from.pan_deg, from.tilt_deg).inverse() * point_in_l;
  constexpr double kStepDeg = 1e-3;
  Eigen::Matrix<double, 2, 4> d = Eigen::Matrix<double, 2, 4>::Zero();
  for (int j = 0; j < 4; ++j) {
    RigPose a = from, b = to;
    (j == 0 ? a.pan_deg : j == 1 ? a.tilt_deg : j == 2 ? b.pan_deg : b.tilt_deg) += kStepDeg;
    const Eigen::Vector3d point =
        calibration.LFromCamera(Side::kLeft, a.pan_deg, a.tilt_deg) * in_camera;
    Eigen::Vector2d moved;
    if (left.Project(calibration.LFromCamera(Side::kLeft, b.pan_deg, b.tilt_deg).inverse() * point,
                     &moved))
      d.col(j) = (moved - projected) / kStepDeg;
  }
  return d;
}

}  // namespace

RigSeams MeasureRigSeams(const RigAdjustmentInput& in, const Calibration& calibration,
                         const RigAdjustment& adjustment, int station) {
  const CameraModel left(calibration.rig.left);
  const double c = calibration.rig.left.principal_distance_px;
  const auto l_from_left = [](const Calibration& of, const RigPose& pose) {
    return of.LFromCamera(Side::kLeft, pose.pan_deg, pose.tilt_deg);
  };
  // Each station's points were intersected with its own levelling; a levelling turns all of a
  // station's poses alike, so the seams do not depend on the one `stage` carries.
  std::vector<Calibration> intersected;
  for (size_t s = 0; s < in.Stations().size(); ++s)
    intersected.push_back(in.CalibrationOf(static_cast<int>(s)));
  std::vector<int> first_pose(in.points.size(), -1);
  // Each point's first observation: its pair's (of a panorama's tie point, its left image's).
  std::vector<size_t> first_observation(in.points.size(), 0);
  // A control field's targets are not seams: no pair intersected them.
  std::vector<char> left_out = in.ControlPoints();
  for (size_t i = 0; i < in.observations.size(); ++i) {
    const RigTieObservation& t = in.observations[i];
    if (first_pose[t.point] < 0) first_pose[t.point] = t.pose, first_observation[t.point] = i;
    if (i < adjustment.rejected_observation.size() && adjustment.rejected_observation[i])
      left_out[t.point] = 1;
  }
  RigSeams seams;
  std::vector<double> px, mm;
  int within = 0;
  for (size_t i = 0; i < in.observations.size(); ++i) {
    const RigTieObservation& t = in.observations[i];
    const int k = first_pose[t.point];
    if (t.pose == k || t.side != Side::kLeft || left_out[t.point]) continue;
    if (station >= 0 && in.poses[k].station != station) continue;
    // The pair's point, moved with its pose's left camera from the input's calibration to
    // `calibration`.
    const Eigen::Isometry3d move =
        l_from_left(calibration, in.poses[k]) *
        l_from_left(intersected[in.poses[k].station], in.poses[k]).inverse();
    const Eigen::Vector3d point = move * in.points[t.point];
    const Eigen::Isometry3d camera_from_l = l_from_left(calibration, in.poses[t.pose]).inverse();
    const Eigen::Vector3d in_camera = camera_from_l * point;
    Eigen::Vector2d projected;
    CameraModel::Jacobian2x3 d_pixel;
    if (!left.Project(in_camera, &projected, &d_pixel)) continue;
    // The disagreement is the difference of two image measurements, the pair's and the
    // neighbour's, each with its sigma; of where the two poses really stood about their
    // read-back angles (the encoders' sigma); and of the pair's intersection.
    const double pair_sigma = adjustment.observation_sigma_px[first_observation[t.point]];
    const double sigma = adjustment.observation_sigma_px[i];
    Eigen::Matrix2d predicted =
        (pair_sigma * pair_sigma + sigma * sigma) * Eigen::Matrix2d::Identity();
    const Eigen::Matrix<double, 2, 4> d_angles =
        SeenAcrossTheAngles(calibration, left, in.poses[k], in.poses[t.pose], point, projected);
    predicted += std::pow(adjustment.encoder_sigma_deg, 2) * d_angles * d_angles.transpose();
    if (static_cast<size_t>(t.point) < in.point_covariance_m2.size()) {
      const Eigen::Matrix<double, 2, 3> d = d_pixel * camera_from_l.linear() * move.linear();
      predicted += d * in.point_covariance_m2[t.point] * d.transpose();
    }
    RigSeamTie tie;
    tie.pose = t.pose;
    tie.pixel = t.pixel;
    tie.disagreement_px = projected - t.pixel;
    const double length = tie.disagreement_px.norm();
    tie.ratio = predicted.trace() > 0.0 ? length / std::sqrt(predicted.trace()) : 0.0;
    within += tie.ratio <= 2.0;
    px.push_back(length);
    mm.push_back(1e3 * length * in_camera.norm() / c);
    tie.azimuth_elevation_deg = {
        std::atan2(point.x(), point.y()) * 180.0 / M_PI,
        std::atan2(point.z(), std::hypot(point.x(), point.y())) * 180.0 / M_PI};
    seams.ties.push_back(tie);
  }
  seams.median_px = Median(px);
  seams.median_mm = Median(mm);
  if (!seams.ties.empty()) seams.within_2_sigma = static_cast<double>(within) / seams.ties.size();
  return seams;
}

}  // namespace ts
