#pragma once
// A control field session's images, loaded to measure the field's targets in them (calibrate
// camera|stereo at a field, issue 20; calibrate rig with a field, issue 21): each image with
// its hand marks, checked against the camera that measures it; and where a session taken at
// recorded stage poses keeps its pairs.
#include <string>
#include <vector>

#include "processing/calibration/field_calibration.h"
#include "processing/calibration/rig_adjustment.h"

namespace ts {

struct FieldSessionFiles {
  std::vector<std::string> left, right;  // per pair
  std::vector<RigPose> poses;            // the stage's read-back per pair
};

// `capture --calibration field`'s station directory (station.json: each pair's files and
// encoder read-back) or `sim render --calibration field`'s (session.json's stage_poses, the
// images in left/ and right/). Throws CommandError naming the file and the field.
FieldSessionFiles LoadFieldSessionFiles(const std::string& dir);

// Throws CommandError naming the file: unreadable, or another size than the camera's (which
// `camera_source` names).
std::vector<FieldImage> LoadFieldImages(const std::vector<std::string>& files,
                                        const std::vector<ImageMarks>& marks,
                                        const CameraIntrinsics& camera,
                                        const std::string& camera_source);

// A control field session's files as the calibration commands take them: image globs (the
// commands expand them), the field, the hand marks and the design calibration to start from.
struct FieldSessionInputs {
  std::string dir, left_images, right_images, field, marks, design;
};
// `sim render --calibration field`'s session (sim::WriteFieldSession): left/, right/,
// field.yaml, marks.yaml, design.yaml.
FieldSessionInputs SimulatedFieldSession(const std::string& dir);

// The field team's calibration of a session, as `topostation` arguments (the program left
// out): `calibrate stereo` on its images from the design values (the stage's too) into
// `cameras`, then `calibrate rig --field-session` on the same session from `cameras` into
// `out`: the targets fix where each camera stands at each pose, which places the cameras over
// the tilt axis where no station's panorama can.
std::vector<std::vector<std::string>> FieldCalibrationCommands(const FieldSessionInputs& session,
                                                               const std::string& cameras,
                                                               const std::string& out);

}  // namespace ts
