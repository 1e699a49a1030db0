#pragma once
// A control field session of the rig projected exactly, for tests of the rig adjustment: seed
// 003's calibration range (9 pans x 4 tilts), its targets seen by the true cameras at their
// true poses with 0.05 px of noise, the surveyed coordinates with the survey's 1 mm: the views
// as MeasureFieldTargets leaves them, without rendering.
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "processing/calibration/rig_adjustment.h"
#include "processing/calibration/target_views.h"
#include "sim/calibration_field.h"
#include "sim/sim_rig.h"

namespace ts::testing {

struct ProjectedFieldSession {
  sim::FieldSession session;
  std::vector<TargetViews> measured;  // left, right
  std::vector<RigPose> poses;         // the encoders' read-backs
};

inline ProjectedFieldSession ProjectFieldSession(const sim::SimRig& rig, uint64_t seed) {
  ProjectedFieldSession f;
  f.session = sim::PlanFieldSession(rig, seed, sim::FieldSessionOptions{});
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::normal_distribution<double> encoder(0.0, RigAdjustmentOptions{}.encoder_sigma_deg);
  for (const StagePose& pose : f.session.poses)
    f.poses.push_back({pose.pan_deg + encoder(rng), pose.tilt_deg + encoder(rng)});
  for (Side side : {Side::kLeft, Side::kRight}) {
    TargetViews& views = f.measured.emplace_back();
    const CameraIntrinsics& camera = side == Side::kLeft ? rig.truth.rig.left : rig.truth.rig.right;
    views.width_px = camera.width_px;
    views.height_px = camera.height_px;
    for (const FieldTarget& t : f.session.surveyed.targets) {
      views.target.push_back(t.position_m);
      views.target_sigma.push_back(t.sigma_m);
    }
    const CameraModel model(camera);
    for (size_t k = 0; k < f.session.poses.size(); ++k) {
      const Eigen::Isometry3d camera_from_field =
          rig.truth.LFromCamera(side, f.session.poses[k].pan_deg, f.session.poses[k].tilt_deg)
              .inverse() *
          f.session.field_from_station.inverse();
      TargetView view{"view", static_cast<int>(k), {}, {}};
      for (size_t i = 0; i < f.session.truth.targets.size(); ++i) {
        Eigen::Vector2d pixel;
        const Eigen::Vector3d p = camera_from_field * f.session.truth.targets[i].position_m;
        if (p.z() <= 0.0 || !model.Project(p, &pixel) || !model.InImage(pixel)) continue;
        view.ids.push_back(static_cast<int>(i));
        view.pixels.push_back(pixel + Eigen::Vector2d(noise(rng), noise(rng)));
      }
      if (view.ids.size() >= 6) views.views.push_back(std::move(view));
    }
  }
  return f;
}

}  // namespace ts::testing
