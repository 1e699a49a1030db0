#pragma once
// What a client may ask of a job (POST /jobs), checked field by field before anything is
// created: the station fields a gravity crew records, and the few capture choices.
//
//   {"kind": "survey" | "capture" | "process", "station": "G-0412", "line": "L7",
//    "instrument_height_m": 1.52, "operator": "...", "notes": "...",
//    "gnss": {"lat_deg": 47.1, "lon_deg": 8.3, "height_m": 512.0, "sigma_m": 0.02},
//    "gcps": [{"id": "p1", "x": ..., "y": ..., "z": ..., "sigma_m": 0.02}],
//    "single_row": false, "required_sigma_mgal": 0.01}   (what the verdict judges against)
//   {"kind": "retake", "station": "G-0412", "poses": [{"pan_deg": 90, "tilt_deg": -12.7}]}
//    (the poses a verdict named, taken again, then the station processed anew)
//   {"kind": "calibrate_rig", "stations": ["G-0412", "G-0413"], "refine_cameras": false}
//    (calibrate rig on those stations; refine_cameras as its --refine-cameras)
//   {"kind": "capture_field", "station": "field-2026-11", "field_pan_deg": 40,
//    "field_tilt_deg": 5, "field_pans": 9, "field_tilts": 4}   (a calibration session, named
//    by its station id; the grid as `capture --calibration field` takes it)
//   {"kind": "calibrate_field", "session": "field-2026-11",
//    "control_field": {"version": 1, "targets": [{"id": 101, "x": .., "y": .., "z": .., "sigma_m":
//    0.001,
//                                   "diameter_m": 0.06}, ...]},
//    "marks": [{"image": "raw/p0001_left.png", "targets": [{"id": 101, "x": 812.4, "y": 233.9}]}]}
//    (`calibrate stereo --control-field --marks` on that session: FIELD.yaml's and MARKS.yaml's
//    content as JSON)
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"
#include "processing/io/control_field_file.h"
#include "station/daemon/job_store.h"

namespace ts::daemon {

struct JobRequest {
  JobKind kind = JobKind::kSurvey;
  std::string station;  // calibrate_rig: the first of `stations`; calibrate_field: the session
  std::vector<std::string> stations;  // calibrate_rig
  nlohmann::json fields;              // the request less kind: kept as the job's parameters
  double instrument_height_m = 0.0;
  bool single_row = false;
};

// Errors name the field: "instrument_height_m: must be within (0, 10] m".
Result<JobRequest> ParseJobRequest(const nlohmann::json& body);

// A calibrate_field request's (or job's) control field and marks, read as their files are.
Result<ControlField> ControlFieldOf(const nlohmann::json& fields);
Result<std::vector<ImageMarks>> TargetMarksOf(const nlohmann::json& fields);

}  // namespace ts::daemon
