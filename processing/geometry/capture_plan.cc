#include "processing/geometry/capture_plan.h"

#include <cmath>
#include <stdexcept>

#include "processing/geometry/rotation.h"

namespace ts {

bool CapturePlanOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  for (double t : tilts_deg)
    if (!(std::abs(t) <= max_abs_tilt_deg)) {
      if (why) *why = "tilts_deg must lie within +-max_abs_tilt_deg";
      return false;
    }
  return true;
}

double AutomaticTiltDeg(const Calibration& cal, const CapturePlanOptions& o) {
  const CameraIntrinsics& c = cal.rig.left;
  const double height = std::max(cal.stage.height_above_mark_m, 0.1);
  // Angle from the optical axis up to the top edge of the image (row -0.5).
  const double half_up = std::atan((c.principal_point_y_px + 0.5) / c.principal_distance_px);
  const double far_depression = std::atan(height / o.far_range_m);
  return DegFromRad(-far_depression + RadFromDeg(o.margin_deg) - half_up);
}

double NearestGroundRangeM(const Calibration& cal, double tilt_deg) {
  const CameraIntrinsics& c = cal.rig.left;
  const double half_down =
      std::atan((c.height_px - 0.5 - c.principal_point_y_px) / c.principal_distance_px);
  const double depression = -RadFromDeg(tilt_deg) + half_down;
  if (depression <= 0.0) return INFINITY;
  return std::max(cal.stage.height_above_mark_m, 0.1) / std::tan(depression);
}

bool UpperPose(const Calibration& cal, const StagePose& below, const CapturePlanOptions& o,
               StagePose* upper) {
  const CameraIntrinsics& c = cal.rig.left;
  const double field_deg =
      DegFromRad(std::atan((c.principal_point_y_px + 0.5) / c.principal_distance_px) +
                 std::atan((c.height_px - 0.5 - c.principal_point_y_px) / c.principal_distance_px));
  const double wanted = below.tilt_deg + field_deg - o.row_overlap_deg;
  const double tilt = std::min(wanted, o.max_abs_tilt_deg);
  if (wanted - tilt > 0.5 * field_deg) return false;
  *upper = {below.pan_deg, tilt};
  return true;
}

std::vector<StagePose> MakeCapturePlan(const Calibration& cal, const CapturePlanOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("capture plan: " + why);
  std::vector<double> tilts = o.tilts_deg;
  if (tilts.empty()) tilts.push_back(AutomaticTiltDeg(cal, o));
  std::vector<StagePose> poses;
  for (double tilt : tilts) {
    if (std::abs(tilt) > o.max_abs_tilt_deg)
      throw std::invalid_argument("capture plan: tilt " + std::to_string(tilt) +
                                  " deg is beyond the stage limit");
    for (int k = 0; k < o.azimuths; ++k) {
      double pan = std::fmod(o.first_pan_deg + 360.0 * k / o.azimuths, 360.0);
      if (pan < 0.0) pan += 360.0;
      poses.push_back({pan, tilt});
    }
  }
  return poses;
}

std::vector<StagePose> MakeFieldPoseGrid(const FieldPoseGrid& g) {
  std::vector<StagePose> poses;
  for (int j = 0; j < g.tilts; ++j)
    for (int i = 0; i < g.pans; ++i)
      poses.push_back({g.centre_pan_deg + (i - 0.5 * (g.pans - 1)) * g.pan_step_deg,
                       g.centre_tilt_deg + (j - 0.5 * (g.tilts - 1)) * g.tilt_step_deg});
  return poses;
}

}  // namespace ts
