#pragma once
// `capture --calibration field|chessboard|charuco`: calibration views with the rig.
//   field       a grid of stage poses around the field's direction (MakeFieldPoseGrid), taken
//               as a station directory (capture.h: resumable, validated); marks and the field
//               file then go to `calibrate stereo --control-field`.
//   chessboard  pairs on demand while a helper moves the board (board_capture.h): Enter on a
//   charuco     terminal, or every --interval seconds, until --pairs are kept.
#include <CLI/CLI.hpp>
#include <string>

#include "acquisition/capture.h"
#include "processing/geometry/capture_plan.h"
#include "station/board_flags.h"

namespace ts {

struct CalibrationCaptureArgs {
  std::string kind;  // field | chessboard | charuco; empty: a station's panorama
  FieldPoseGrid grid;
  BoardFlags board;
  double interval_s = 0.0;  // 0: a pair when Enter is pressed
  int pairs = 0;            // stop when this many are kept (0: at the end of input or Ctrl-C)
};

void AddCalibrationCaptureFlags(CLI::App* cmd, CalibrationCaptureArgs* args);

// Throws CommandError. options: the capture's (exposure, timeouts, format).
void RunCalibrationCapture(const CalibrationCaptureArgs& args, const RigConfig& rig,
                           const std::string& out, bool resume, CaptureOptions options, bool json);

}  // namespace ts
