#pragma once
// The capture plan: the stage poses of a panorama. One implementation, used by the simulator
// (`sim render`) and by acquisition alike.
//
// Default: 12 azimuths 30 deg apart at one downward tilt, chosen from the rig geometry so that
// the ground at far_range_m (the corners of the 60 m square are 42.4 m away) lies margin_deg
// below the top edge of the image, and the bottom edge sees the ground a few metres from the
// tripod. The margin is 5 deg (~160 px with the paper's rig): the ground beyond 30 m is only
// a few dozen rows high at grazing view, and matching windows lose the rows at the edge;
// with a 1 deg margin nothing beyond 30 m was matched on flat ground (DEM coverage of the 60 m
// square 79 %, 100 % with 5 deg), and ground rising above the station's is seen too. With
// the paper's rig (vertical field of view 31 deg) at 1.5 m the ground is seen from ~2.9 m,
// and neighbouring views overlap by about 11 deg of their 41 deg width.
#include <string>
#include <vector>

#include "core/options.h"
#include "core/stage_pose.h"
#include "processing/geometry/calibration.h"

namespace ts {

struct CapturePlanOptions {
  int azimuths = 12;               // poses per row, evenly spaced over 360 deg
  double first_pan_deg = 0.0;      // pan of the first pose
  std::vector<double> tilts_deg;   // rows; empty = one row at AutomaticTiltDeg()
  double far_range_m = 42.5;       // ground range the top image edge must reach
  double margin_deg = 5.0;         // the top edge looks this much above that ground point
  double max_abs_tilt_deg = 32.0;  // stage limit
  // Poses higher up where the terrain goes on above a view (terrain_above_view.h): the
  // capture decides them pose by pose and appends them to the plan.
  bool upper_poses = true;
  double row_overlap_deg = 6.0;  // an upper pose's view overlaps the one below by this much
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("azimuths", self.azimuths, {"poses per row", "", 1, 360});
    v("first_pan_deg", self.first_pan_deg, {"pan of the first pose", "deg", -360, 360});
    v("far_range_m", self.far_range_m,
      {"ground range the top image edge must reach", "m", 1, 1000});
    v("margin_deg", self.margin_deg, {"the top edge looks this much above it", "deg", -45, 45});
    v("max_abs_tilt_deg", self.max_abs_tilt_deg, {"stage tilt limit", "deg", 0.1, 90});
    v("upper_poses", self.upper_poses, {"poses higher up where the terrain goes on above a view"});
    v("row_overlap_deg", self.row_overlap_deg,
      {"an upper pose overlaps the one below by this", "deg", 0, 19.99});
  }
  bool Check(std::string* why) const;
};

// Tilt (deg, negative = down) putting the top image edge margin_deg above the ground at
// far_range_m, for a camera height of calibration.stage.height_above_mark_m.
double AutomaticTiltDeg(const Calibration& calibration, const CapturePlanOptions& options);
// Nearest ground range seen by the bottom image edge at a given tilt (flat ground).
double NearestGroundRangeM(const Calibration& calibration, double tilt_deg);

// The pose above `below` on the same azimuth, its view overlapping by row_overlap_deg; none
// (false) when that would pass the stage limit by more than half a view.
bool UpperPose(const Calibration& calibration, const StagePose& below,
               const CapturePlanOptions& options, StagePose* upper);

// Throws std::invalid_argument when the options are invalid or a tilt exceeds the limit.
std::vector<StagePose> MakeCapturePlan(const Calibration& calibration,
                                       const CapturePlanOptions& options);

// The stage poses of a calibration at a control field (seed 003 §3): a grid of pans and tilts
// around the direction of the field, so that its targets sweep across every part of both
// frames. The relative orientation's angles are determined as well as the principal points
// (a shift of one is a turn of the other): 9 pans 7.5 deg apart and 4 tilts 5.5 deg apart
// bring them within 0.005 deg with a field 100 x 44 deg wide at 5-30 m.
struct FieldPoseGrid {
  double centre_pan_deg = 0.0;  // where the field is, seen from the stage
  double centre_tilt_deg = 0.0;
  int pans = 9;
  double pan_step_deg = 7.5;
  int tilts = 4;
  double tilt_step_deg = 5.5;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("centre_pan_deg", self.centre_pan_deg, {"pan towards the field's centre", "deg", -360, 360});
    v("centre_tilt_deg", self.centre_tilt_deg, {"tilt towards the field's centre", "deg", -90, 90});
    v("pans", self.pans, {"stage pans", "", 1, 36});
    v("pan_step_deg", self.pan_step_deg, {"between pans", "deg", 0, 90});
    v("tilts", self.tilts, {"stage tilts", "", 1, 9});
    v("tilt_step_deg", self.tilt_step_deg, {"between tilts", "deg", 0, 30});
  }
};
// Row by row, from the lowest tilt; each row from the smallest pan.
std::vector<StagePose> MakeFieldPoseGrid(const FieldPoseGrid& grid);

}  // namespace ts
