#pragma once
// A control field (seed 003 §3, seed 000): circular targets surveyed in a frame of their own,
// and the hand measurements that identify a few of them in the images (seed 003 measures
// "several control points" by hand, the rest are predicted and refined).
//
//   control_field:                       # FIELD.yaml
//     version: 1
//     targets:                           # coordinates in metres, sigma of each coordinate
//       - {id: 101, x: 512.113, y: 208.530, z: 31.004, sigma_m: 0.001, diameter_m: 0.06}
//
//   marks:                               # MARKS.yaml: pixel positions measured by hand
//     - image: left/01.png               # matched to the end of an image's path
//       targets: [{id: 101, x: 812.4, y: 233.9}, ...]
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

struct FieldTarget {
  int id = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double sigma_m = 0.0;     // of each coordinate; 0: exact
  double diameter_m = 0.0;  // of the bright disc
};

struct ControlField {
  std::vector<FieldTarget> targets;
  int IndexOf(int id) const;  // -1 when the field has no such target
};

struct TargetMark {
  int id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
};

struct ImageMarks {
  std::string image;  // the end of an image's path: "left/01.png"
  std::vector<TargetMark> marks;
};

// Errors name the file and the field: "FIELD.yaml: control_field.targets[3].id: 101 twice".
Result<ControlField> LoadControlField(const std::string& file);
Status SaveControlField(const ControlField& field, const std::string& file);

Result<std::vector<ImageMarks>> LoadTargetMarks(const std::string& file);
Status SaveTargetMarks(const std::vector<ImageMarks>& marks, const std::string& file);
// The same from text (YAML, or JSON, which YAML reads): a request to the daemon. Errors name
// the field only: "control_field.targets[3].id: 101 twice".
Result<ControlField> ParseControlField(const std::string& text);
Result<std::vector<ImageMarks>> ParseTargetMarks(const std::string& text);

// The marks of an image: the entry whose name ends its path at a path separator (null: none).
const ImageMarks* MarksOfImage(const std::vector<ImageMarks>& marks, const std::string& path);

}  // namespace ts
