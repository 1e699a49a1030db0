#include "processing/calibration/rig_control_field.h"

#include <Eigen/Geometry>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "processing/calibration/target_adjustment.h"

namespace ts {
namespace {

// The field's pose in L from each view's resection, the cameras placed by the start stage: the
// mean rotation (quaternions on one hemisphere, normalised) and the mean translation.
std::optional<Eigen::Isometry3d> StartFieldPose(const Calibration& calibration,
                                                const std::vector<TargetViews>& measured,
                                                const std::vector<RigPose>& poses) {
  Eigen::Vector4d quaternions = Eigen::Vector4d::Zero();
  Eigen::Vector3d translations = Eigen::Vector3d::Zero();
  int count = 0;
  std::optional<Eigen::Quaterniond> first;
  for (size_t c = 0; c < measured.size(); ++c) {
    const Side side = c == 0 ? Side::kLeft : Side::kRight;
    const CameraIntrinsics& camera =
        side == Side::kLeft ? calibration.rig.left : calibration.rig.right;
    for (const TargetView& v : measured[c].views) {
      std::vector<Eigen::Vector3d> target;
      for (int id : v.ids) target.push_back(measured[c].target[id]);
      const std::optional<Eigen::Isometry3d> camera_from_field = Resect(target, v.pixels, camera);
      if (!camera_from_field) continue;
      const RigPose& pose = poses[v.placement];
      const Eigen::Isometry3d l_from_field =
          calibration.LFromCamera(side, pose.pan_deg, pose.tilt_deg) * *camera_from_field;
      Eigen::Quaterniond q(l_from_field.linear());
      if (!first) first = q;
      if (q.dot(*first) < 0.0) q.coeffs() *= -1.0;
      quaternions += q.coeffs();
      translations += l_from_field.translation();
      ++count;
    }
  }
  if (count == 0) return std::nullopt;
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  mean.linear() = Eigen::Quaterniond(quaternions.normalized()).toRotationMatrix();
  mean.translation() = translations / count;
  return mean;
}

}  // namespace

Result<RigAdjustmentInput> ControlFieldInput(const Calibration& calibration,
                                             const std::vector<TargetViews>& measured,
                                             const std::vector<RigPose>& poses) {
  if (measured.empty() || measured.size() > 2)
    return Error{"control field: the left camera's views, or both cameras', are needed"};
  for (const TargetViews& camera : measured)
    for (const TargetView& v : camera.views)
      if (v.placement < 0 || v.placement >= static_cast<int>(poses.size()))
        return Error{fmt::format("control field: {} names stage pose {} of {}", v.name,
                                 v.placement + 1, poses.size())};
  const std::optional<Eigen::Isometry3d> l_from_field =
      StartFieldPose(calibration, measured, poses);
  if (!l_from_field) return Error{"control field: no view's targets give its pose"};
  RigAdjustmentInput in;
  in.calibration = calibration;
  in.poses = poses;
  for (RigPose& pose : in.poses) pose.station = 0;
  RigStation setup;
  setup.levelling_deg = {calibration.stage.levelling_x_deg, calibration.stage.levelling_y_deg};
  in.stations = {setup};
  RigControlField field;
  field.l_from_field = *l_from_field;
  std::map<int, int> point_of;  // target id -> point
  for (size_t c = 0; c < measured.size(); ++c)
    for (const TargetView& v : measured[c].views)
      for (size_t k = 0; k < v.ids.size(); ++k) {
        const int id = v.ids[k];
        auto [it, added] = point_of.emplace(id, static_cast<int>(in.points.size()));
        if (added) {
          in.points.push_back(*l_from_field * measured[c].target[id]);
          field.points.push_back(it->second);
          field.surveyed.push_back(measured[c].target[id]);
          field.sigma_m.push_back(static_cast<size_t>(id) < measured[c].target_sigma.size()
                                      ? measured[c].target_sigma[id]
                                      : 0.0);
        }
        in.observations.push_back(
            {v.placement, c == 0 ? Side::kLeft : Side::kRight, it->second, v.pixels[k]});
      }
  in.control_fields = {std::move(field)};
  return in;
}

}  // namespace ts
