#pragma once
// The calibrate jobs, run as child processes beside the daemon's own binary, so that an
// adjustment that fails or is cancelled (killed) takes nothing of the daemon with it:
//   calibrate_rig    `topostation calibrate rig` (issue 21) on stations the daemon keeps: the
//                    stage kinematics;
//   calibrate_field  `topostation calibrate stereo --control-field` and `calibrate rig
//                    --field-session` on a session a capture_field job took: the cameras, the
//                    stereo pair and the stage.
// Each writes a calibration file of the job's own; the rig config is not changed.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"
#include "processing/geometry/calibration.h"
#include "processing/io/control_field_file.h"

namespace ts::daemon {

// `topostation calibrate rig DIRS... --calibration (start) --out out_yaml --json`, with
// --refine-cameras when asked; its JSON report, or the error with the last line it wrote.
// `should_stop` is asked every 100 ms.
Result<nlohmann::json> CalibrateRigInChild(const std::vector<std::string>& station_dirs,
                                           const Calibration& start, bool refine_cameras,
                                           const std::string& out_yaml,
                                           const std::function<bool()>& should_stop);

// `topostation calibrate stereo` on the session's raw images with the field and the marks
// (written into the session as field-job-N.yaml and marks-job-N.yaml, N = `job_id`, a record of
// what was asked), starting from the session's design.yaml, then `calibrate rig
// --field-session` on the same session for the stage; the cameras' JSON report with the
// stage's as "stage", or the error, as above.
Result<nlohmann::json> CalibrateFieldInChild(const std::string& session_dir, int64_t job_id,
                                             const ControlField& field,
                                             const std::vector<ImageMarks>& marks,
                                             const std::string& out_yaml,
                                             const std::function<bool()>& should_stop);

}  // namespace ts::daemon
