// topostation capture --rig RIG.yaml --out STATION [--resume] [--single-row]: the panorama
// (12 pairs, and the poses above uphill views) over the real drivers (Aravis cameras, Modbus
// stage) into a station directory; with --calibration, calibration views (calibration_capture.h).
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "acquisition/capture.h"
#include "devices/aravis_camera.h"
#include "devices/modbus_stage.h"
#include "station/calibration_capture.h"
#include "station/commands.h"
#include "station/option_flags.h"
#include "station/progress_display.h"

namespace ts {
namespace {

struct CaptureArgs {
  std::string rig_file;
  std::string out;
  bool resume = false;
  bool json = false;
  bool mono16 = false;
  bool single_row = false;
  CaptureOptions options;
  CalibrationCaptureArgs calibration;
};

void Run(const CaptureArgs& args) {
  const Result<RigConfig> rig = LoadRigConfig(args.rig_file);
  if (!rig) throw CommandError(rig.error());
  CaptureOptions options = args.options;
  options.plan.upper_poses = !args.single_row;
  options.format = args.mono16 ? PixelFormat::kMono16 : PixelFormat::kMono8;
  if (!args.calibration.kind.empty())
    return RunCalibrationCapture(args.calibration, *rig, args.out, args.resume, options, args.json);
  const CaptureSummary s =
      CaptureOrThrow(*rig, args.out, args.resume, options, ::isatty(STDERR_FILENO) && !args.json);
  if (args.json) {
    std::printf("%s\n", nlohmann::json{{"station", args.out},
                                       {"total_pairs", s.total_pairs},
                                       {"captured_now", s.captured_now},
                                       {"already_present", s.already_present},
                                       {"retakes", s.retakes},
                                       {"frame_retries", s.frame_retries},
                                       {"resent_packets", s.resent_packets},
                                       {"exposure_us", s.exposure_us},
                                       {"seconds", s.seconds},
                                       {"timeline", s.timeline}}
                            .dump()
                            .c_str());
  } else {
    std::printf("%s: %d of %d pairs captured now (%d already there) in %.1f s\n", args.out.c_str(),
                s.captured_now, s.total_pairs, s.already_present, s.seconds);
    if (s.timeline.is_object()) {
      const nlohmann::json& t = s.timeline["total_s"];
      std::printf(
          "  waiting for the stage %.1f s, trigger to frame %.1f s, verify %.1f s, "
          "write %.1f s (while the stage moves)\n",
          t.value("stage_wait_s", 0.0), t.value("trigger_to_frame_s", 0.0),
          t.value("verify_s", 0.0), t.value("write_s", 0.0));
    }
  }
}

}  // namespace

CaptureSummary CaptureOrThrow(const RigConfig& rig, const std::string& out, bool resume,
                              const CaptureOptions& options, bool show_progress,
                              const std::function<void(const CaptureEvent&)>& observer) {
  auto stage = OpenModbusStage(rig.stage);
  if (!stage) throw CommandError(stage.error());
  auto left = OpenAravisCamera(rig.left_camera);
  if (!left) throw CommandError(left.error());
  auto right = OpenAravisCamera(rig.right_camera);
  if (!right) throw CommandError(right.error());
  ProgressDisplay display(show_progress);
  auto progress = [&](const CaptureEvent& e) {
    const std::string pair = "pair " + std::to_string(e.pair);
    if (e.kind == CaptureEventKind::kStarted) display.Line("capture: " + e.message);
    if (e.kind == CaptureEventKind::kMoving || e.kind == CaptureEventKind::kPairCaptured)
      display.Count("capture: pair", e.captured, e.total);
    if (e.kind == CaptureEventKind::kRetake) display.Line(pair + " retaken: " + e.message);
    if (e.kind == CaptureEventKind::kUpperPose) display.Line(pair + ": " + e.message);
    if (e.kind == CaptureEventKind::kFrameRetry)
      display.Line(pair + " triggered again: " + e.message);
    if (observer) observer(e);
  };
  Result<CaptureSummary> s =
      CaptureStation(**stage, **left, **right, rig, out, resume, options, progress);
  display.Clear();
  if (!s) throw CommandError(s.error());
  return *s;
}

void AddCaptureCommand(CLI::App& app) {
  auto args = std::make_shared<CaptureArgs>();
  CLI::App* cmd =
      app.add_subcommand("capture", "Capture the stereo panorama with the rig's cameras and stage");
  cmd->add_option("--rig", args->rig_file, "rig config (YAML)")->required();
  cmd->add_option("--out", args->out, "station directory")->required();
  cmd->add_flag("--resume", args->resume, "complete an interrupted station");
  AddDeclaredOption(cmd, "--azimuths", args->options, "plan.azimuths");
  AddDeclaredOption(cmd, "--exposure-us", args->options, "initial_exposure_us");
  cmd->add_flag("--mono16", args->mono16, "16-bit images");
  cmd->add_flag("--single-row", args->single_row,
                "no poses higher up where the terrain goes on above a view");
  cmd->add_flag("--json", args->json, "print the summary as JSON");
  AddCalibrationCaptureFlags(cmd, &args->calibration);
  cmd->callback([args] { Run(*args); });
}

}  // namespace ts
