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

}  // namespace ts
