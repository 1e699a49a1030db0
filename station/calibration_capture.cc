#include "station/calibration_capture.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "acquisition/board_capture.h"
#include "devices/aravis_camera.h"
#include "processing/io/calibration_yaml.h"
#include "station/commands.h"
#include "station/option_flags.h"

namespace ts {
namespace {

void RunFieldCapture(const CalibrationCaptureArgs& args, const RigConfig& rig,
                     const std::string& out, bool resume, CaptureOptions options, bool json) {
  options.given_plan = MakeFieldPoseGrid(args.grid);
  options.plan.upper_poses = false;
  const CaptureSummary s =
      CaptureOrThrow(rig, out, resume, options, ::isatty(STDERR_FILENO) && !json);
  // The cameras the field calibration starts from: the rig's present calibration.
  const std::string start = out + "/design.yaml";
  if (Status st = SaveCalibrationYaml(rig.calibration, start); !st) throw CommandError(st.error());
  const std::string calibrate = "topostation calibrate stereo --left '" + out +
                                "/raw/*_left.png' --right '" + out +
                                "/raw/*_right.png' --control-field FIELD.yaml --marks MARKS.yaml "
                                "--start " +
                                start + " --out CAL.yaml";
  if (json) {
    std::printf("%s\n", nlohmann::json{{"station", out},
                                       {"stage_poses", s.total_pairs},
                                       {"captured_now", s.captured_now},
                                       {"already_present", s.already_present},
                                       {"seconds", s.seconds},
                                       {"calibrate", calibrate}}
                            .dump()
                            .c_str());
    return;
  }
  std::printf(
      "%s: %d of %d stage poses at the field captured now (%d already there) in %.1f s\n"
      "next: mark 4 or more targets in one image of each pose (MARKS.yaml, images named "
      "raw/pair_NN_left.png), then\n  %s\n",
      out.c_str(), s.captured_now, s.total_pairs, s.already_present, s.seconds, calibrate.c_str());
}

// Waits for the operator (a line on stdin; false at its end or on "q") or for the interval.
bool NextPairWanted(const CalibrationCaptureArgs& args,
                    std::chrono::steady_clock::time_point* next_at) {
  if (args.interval_s > 0.0) {
    std::this_thread::sleep_until(*next_at);
    *next_at += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(args.interval_s));
    return true;
  }
  if (::isatty(STDIN_FILENO))
    std::fprintf(stderr, "Enter: take a pair; q or Ctrl-D: stop > "), std::fflush(stderr);
  std::string line;
  return static_cast<bool>(std::getline(std::cin, line)) && line != "q";
}

void RunBoardCapture(const CalibrationCaptureArgs& args, const RigConfig& rig,
                     const std::string& out, const CaptureOptions& options, bool json) {
  const CalibrationBoard board = ParseBoardFlags(args.board);
  auto left = OpenAravisCamera(rig.left_camera);
  if (!left) throw CommandError(left.error());
  auto right = OpenAravisCamera(rig.right_camera);
  if (!right) throw CommandError(right.error());
  auto capture = BoardCapture::Open(**left, **right, out, board, options);
  if (!capture) throw CommandError(capture.error());
  BoardCapture& c = **capture;
  std::fprintf(stderr, "%s: %s, %d pairs kept already\n", out.c_str(), board.Describe().c_str(),
               c.kept());
  nlohmann::json taken = nlohmann::json::array();
  int not_kept = 0;
  auto next_at = std::chrono::steady_clock::now();
  while ((args.pairs == 0 || c.kept() < args.pairs) && NextPairWanted(args, &next_at)) {
    const Result<BoardPair> pair = c.TakePair();
    if (!pair) throw CommandError(pair.error());
    std::fprintf(stderr, "%s\n", pair->Summary().c_str());
    not_kept += pair->kept ? 0 : 1;
    taken.push_back({{"name", pair->name},
                     {"kept", pair->kept},
                     {"corners_left", pair->corners_left},
                     {"corners_right", pair->corners_right}});
  }
  const std::string session = out + "/session.json";
  if (json) {
    std::printf("%s\n", nlohmann::json{{"dir", out},
                                       {"kept", c.kept()},
                                       {"not_kept", not_kept},
                                       {"retakes", c.summary().retakes},
                                       {"frame_retries", c.summary().frame_retries},
                                       {"pairs", taken},
                                       {"session", session}}
                            .dump()
                            .c_str());
    return;
  }
  std::printf(
      "%s: %d pairs kept (%d without a board dropped); the command that calibrates "
      "them is in %s\n",
      out.c_str(), c.kept(), not_kept, session.c_str());
}

}  // namespace

void AddCalibrationCaptureFlags(CLI::App* cmd, CalibrationCaptureArgs* args) {
  cmd->add_option("--calibration", args->kind,
                  "calibration views instead of a panorama: field (a grid of stage poses at a "
                  "control field), chessboard or charuco (pairs on demand while the board is "
                  "moved)")
      ->check(CLI::IsMember({"field", "chessboard", "charuco"}));
  AddDeclaredOption(cmd, "--field-pan-deg", args->grid, "centre_pan_deg");
  AddDeclaredOption(cmd, "--field-tilt-deg", args->grid, "centre_tilt_deg");
  AddDeclaredOption(cmd, "--field-pans", args->grid, "pans");
  AddDeclaredOption(cmd, "--field-pan-step-deg", args->grid, "pan_step_deg");
  AddDeclaredOption(cmd, "--field-tilts", args->grid, "tilts");
  AddDeclaredOption(cmd, "--field-tilt-step-deg", args->grid, "tilt_step_deg");
  AddBoardFlags(cmd, &args->board);
  cmd->add_option("--interval", args->interval_s,
                  "with a board: a pair every this many seconds (default: on Enter)")
      ->check(CLI::Range(0.0, 3600.0));
  cmd->add_option("--pairs", args->pairs,
                  "with a board: stop when this many pairs are kept (default: at the end of "
                  "input, q, or Ctrl-C; every kept pair is already on disk)")
      ->check(CLI::Range(0, 10000));
}

void RunCalibrationCapture(const CalibrationCaptureArgs& args, const RigConfig& rig,
                           const std::string& out, bool resume, CaptureOptions options, bool json) {
  if (args.kind == "field") return RunFieldCapture(args, rig, out, resume, options, json);
  if ((args.kind == "charuco") != !args.board.charuco_size.empty())
    throw CommandError("--calibration " + args.kind + ": " +
                       (args.kind == "charuco" ? "give the board with --charuco SQUARESxSQUARES"
                                               : "--charuco names a ChArUco board: use "
                                                 "--calibration charuco"));
  RunBoardCapture(args, rig, out, options, json);
}

}  // namespace ts
