#pragma once
// A calibration range for the simulated rig (seed 003 §3, fig. 3): about 200 circular targets
// (a white disc on a black square, facing the pillar) spread over a 3D structure 5-30 m from
// the station, surveyed in a frame of their own with 1 mm noise, and the rig's views of it at
// a grid of stage poses that puts targets in every part of both frames. Each image is
// rendered exactly through the true camera model (every sample's ray met with the target's
// plane), anti-aliased by supersampling, then exposed by the sensor model with its noise. In
// each left image a few targets are "measured by hand" (their true pixels with 0.5 px error),
// as a field team marks them before the rest are found.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "core/stage_pose.h"
#include "processing/geometry/capture_plan.h"
#include "processing/io/control_field_file.h"
#include "sim/sim_rig.h"

namespace ts::sim {

struct FieldSessionOptions {
  int targets = 200;
  double min_distance_m = 5.0;
  double max_distance_m = 30.0;
  double azimuth_span_deg = 100.0;   // of the field, centred on pan 0
  double elevation_span_deg = 44.0;  // centred on the horizon
  // Disc diameter per metre of distance: every target some 11 px across.
  double diameter_per_m = 0.006;
  double survey_sigma_m = 0.001;
  FieldPoseGrid poses;  // centred on the field
  int marks_per_view = 5;
  double mark_sigma_px = 0.5;
  int supersampling = 3;  // per axis
  double exposure_us = 3000.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("targets", self.targets, {"targets in the field", "", 6, 5000});
    v("min_distance_m", self.min_distance_m, {"nearest target", "m", 1, 1000});
    v("max_distance_m", self.max_distance_m, {"farthest target", "m", 1, 1000});
    v("azimuth_span_deg", self.azimuth_span_deg, {"width of the field", "deg", 1, 360});
    v("elevation_span_deg", self.elevation_span_deg, {"height of the field", "deg", 1, 90});
    v("diameter_per_m", self.diameter_per_m,
      {"disc diameter per metre of distance", "", 1e-4, 0.1});
    v("survey_sigma_m", self.survey_sigma_m, {"survey noise of each coordinate", "m", 0, 1});
    v("marks_per_view", self.marks_per_view, {"targets marked by hand per left image", "", 0, 50});
    v("mark_sigma_px", self.mark_sigma_px, {"error of a hand mark", "px", 0, 10});
    v("supersampling", self.supersampling, {"samples per pixel per axis", "", 1, 16});
    v("exposure_us", self.exposure_us, {"exposure time", "us", 10, 1e6});
    v.Group("poses", self.poses);
  }
  bool Check(std::string* why) const;
};

struct FieldSession {
  ControlField truth;     // exact coordinates, in the field's frame
  ControlField surveyed;  // with the survey's noise: what the team is given
  Eigen::Isometry3d field_from_station = Eigen::Isometry3d::Identity();
  std::vector<StagePose> poses;
  std::vector<ImageMarks> marks;
};

// The field and the stage poses, deterministic for the seed, without images.
FieldSession PlanFieldSession(const SimRig& rig, uint64_t seed, const FieldSessionOptions& o);
// One camera's view of the field at a stage pose: its radiance, before the sensor.
cv::Mat RenderFieldView(const SimRig& rig, const FieldSession& session, Side side,
                        const StagePose& pose, int supersampling);

// One camera's image of the field at stage pose `pose`, exposed by the sensor model (Mono8), its
// noise fixed by the seed: what WriteFieldSession writes.
cv::Mat ExposeFieldView(const SimRig& rig, const FieldSession& session, Side side, int pose,
                        uint64_t seed, const FieldSessionOptions& options);

// A session written as the team leaves it, and its truth:
//   DIR/left/NN.png, DIR/right/NN.png   the pairs (Mono8), NN from 01
//   DIR/field.yaml                      the surveyed field (control_field_file.h)
//   DIR/marks.yaml                      the hand marks
//   DIR/design.yaml                     the rig's design calibration (the starting cameras)
//   DIR/session.json                    the stage poses and the command that calibrates
//   TRUTH/calibration.yaml, TRUTH/field.yaml   the true rig and field
Status WriteFieldSession(const SimRig& rig, uint64_t seed, const FieldSessionOptions& options,
                         const std::string& dir, const std::string& truth_dir);

}  // namespace ts::sim
