#include "processing/geometry/capture_plan.h"

#include <cmath>
#include <stdexcept>

#include "processing/geometry/rotation.h"

namespace ts {

bool CapturePlanOptions::Check(std::string* why) const {
  std::string err;
  if (azimuths < 1 || azimuths > 360)
    err = "azimuths must be in [1, 360]";
  else if (!std::isfinite(first_pan_deg))
    err = "first_pan_deg must be finite";
  else if (!(far_range_m > 0.0) || !std::isfinite(far_range_m))
    err = "far_range_m must be > 0";
  else if (!std::isfinite(margin_deg))
    err = "margin_deg must be finite";
  else if (!(max_abs_tilt_deg > 0.0 && max_abs_tilt_deg <= 90.0))
    err = "max_abs_tilt_deg must be in (0, 90]";
  else if (!(row_overlap_deg >= 0.0 && row_overlap_deg < 20.0))
    err = "row_overlap_deg must be in [0, 20)";
  for (double t : tilts_deg)
    if (!std::isfinite(t)) err = "tilts must be finite";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
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

}  // namespace ts
