// topostation calibrate camera | stereo: a camera's interior orientation, or both cameras' and
// their relative orientation in one adjustment, from chessboard views or at a control field
// (issue 20).
#include <glob.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "core/log.h"
#include "processing/calibration/calibration_board.h"
#include "processing/calibration/calibration_validation.h"
#include "processing/calibration/camera_calibration.h"
#include "processing/calibration/field_calibration.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/opencv_calibration_file.h"
#include "station/board_flags.h"
#include "station/calibration_report.h"
#include "station/commands.h"
#include "station/field_session.h"
#include "station/option_flags.h"

namespace ts {
namespace {

struct CalibrateArgs {
  std::string images, left, right;
  BoardFlags board_flags;
  CalibrationBoard board;  // parsed from board_flags
  CameraCalibrationOptions options;
  std::string stage_from;
  // A control field instead of a board: the field, the hand marks, the design calibration.
  std::string control_field, marks, start;
  std::string side = "left";  // calibrate camera: which design camera starts it
  FieldCalibrationOptions field;
  ValidationOptions validation;
  std::string out;
  bool json = false;
  bool AtField() const { return !control_field.empty(); }
};

std::vector<std::string> ExpandGlob(const std::string& flag, const std::string& pattern) {
  glob_t matches{};
  std::vector<std::string> files;
  if (::glob(pattern.c_str(), 0, nullptr, &matches) == 0)
    for (size_t i = 0; i < matches.gl_pathc; ++i) files.emplace_back(matches.gl_pathv[i]);
  ::globfree(&matches);
  if (files.empty()) throw CommandError(flag + ": no file matches '" + pattern + "'");
  return files;  // glob sorts them
}

// The board in every image, the placement its index in the list; an image without the board
// (a ChArUco board: without six of its corners) is named in the log and skipped. The images
// are read and searched side by side (the detector keeps a core busy only in part), one at a
// time per thread; the views, the log and the first error come in the order of the files.
TargetViews DetectBoards(const std::vector<std::string>& files, const CalibrateArgs& args,
                         std::vector<std::string>* skipped) {
  struct Searched {
    bool readable = false;
    cv::Size size;
    std::optional<TargetView> view;
  };
  std::vector<Searched> searched(files.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(files.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const cv::Mat grey = cv::imread(files[i], cv::IMREAD_GRAYSCALE);
      searched[i] = {!grey.empty(), grey.size(), {}};
      if (!grey.empty()) searched[i].view = DetectBoard(grey, args.board);
    }
  });
  TargetViews views;
  views.target = args.board.Corners();
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string& file = files[i];
    Searched& s = searched[i];
    if (!s.readable) throw CommandError(file + ": not a readable image");
    if (views.width_px == 0) views.width_px = s.size.width, views.height_px = s.size.height;
    if (s.size.width != views.width_px || s.size.height != views.height_px)
      throw CommandError(file + ": " + std::to_string(s.size.width) + "x" +
                         std::to_string(s.size.height) + " pixels, the first image has " +
                         std::to_string(views.width_px) + "x" + std::to_string(views.height_px));
    if (s.view) {
      s.view->name = std::filesystem::path(file).filename().string();
      s.view->placement = static_cast<int>(i);
      views.views.push_back(std::move(*s.view));
    } else {
      skipped->push_back(file);
      Log().warn("{}: {} not found{}; view skipped", file, args.board.Describe(),
                 args.board.charuco ? " (fewer than 6 corners)"
                 : args.board.chessboard.circle_markers
                     ? " (no part of it with its three circle markers)"
                     : "");
    }
  }
  return views;
}

// A field session's inputs: the field, the marks, the design calibration, each image with
// its marks.
struct FieldInputs {
  ControlField field;
  FieldViews views;
};

FieldInputs LoadFieldInputs(const CalibrateArgs& args,
                            const std::vector<std::vector<std::string>>& files,
                            const std::vector<Side>& sides) {
  if (args.marks.empty() || args.start.empty())
    throw CommandError(
        "--control-field: give --marks (targets measured by hand) and --start "
        "(the rig's design calibration)");
  Result<ControlField> field = LoadControlField(args.control_field);
  if (!field) throw CommandError(field.error());
  const Result<std::vector<ImageMarks>> marks = LoadTargetMarks(args.marks);
  if (!marks) throw CommandError(marks.error());
  const Result<Calibration> start = LoadCalibrationYaml(args.start);
  if (!start) throw CommandError("--start: " + start.error());
  FieldInputs in{*field, {}};
  for (size_t c = 0; c < files.size(); ++c) {
    in.views.start.push_back(sides[c] == Side::kLeft ? start->rig.left : start->rig.right);
    in.views.images.push_back(LoadFieldImages(files[c], *marks, in.views.start.back(), args.start));
  }
  in.views.second_from_first = start->rig.RightFromLeftCamera();
  return in;
}

void PrintFieldReport(const FieldReport& report) {
  std::printf("control field: %d targets found, matching sigma %.3f px (median)\n",
              report.targets_found, report.target_sigma_px);
  for (const std::string& w : report.warnings) std::printf("warning: %s\n", w.c_str());
}

nlohmann::json FieldJson(const FieldReport& report) {
  return {{"targets_found", report.targets_found},
          {"target_sigma_px", report.target_sigma_px},
          {"warnings", report.warnings}};
}

nlohmann::json CameraJson(const CameraCalibration& c) {
  nlohmann::json sigma = nlohmann::json::object();
  for (int i = 0; i < kIntrinsicCount; ++i)
    sigma[CameraIntrinsics::kParameterNames[i]] = c.sigma[i];
  return {{"rms_px", c.rms_px},
          {"sigma0_px", c.sigma0_px},
          {"fx", c.fx()},
          {"fy", c.fy()},
          {"cx", c.cx()},
          {"cy", c.cy()},
          {"c", c.intrinsics.principal_distance_px},
          {"k1", c.intrinsics.k1},
          {"k2", c.intrinsics.k2},
          {"k3", c.intrinsics.k3},
          {"p1", c.intrinsics.p1},
          {"p2", c.intrinsics.p2},
          {"scale_x", c.intrinsics.scale_x},
          {"shear", c.intrinsics.shear},
          {"sigma", sigma},
          {"high_correlations", c.high_correlations},
          {"fixed_insignificant", c.fixed_insignificant},
          {"views_used", c.view_rms_px.size()},
          {"view_names", c.view_names},
          {"view_rms_px", c.view_rms_px},
          {"observations", c.observations},
          {"rejected", c.rejected},
          {"coverage",
           {{"grid", {FrameCoverage::kColumns, FrameCoverage::kRows}},
            {"share", c.coverage.share},
            {"border_share", c.coverage.border_share},
            {"counts", c.coverage.counts}}},
          {"warnings", c.warnings}};
}

nlohmann::json ValidationJson(const CalibrationValidation& v) {
  nlohmann::json maps = nlohmann::json::array();
  for (const MapValidation& m : v.maps)
    maps.push_back({{"distance_m", m.distance_m},
                    {"max_sigma_px", m.max_sigma_px},
                    {"median_sigma_px", m.median_sigma_px},
                    {"split", m.split},
                    {"max_difference_px", m.max_difference_px},
                    {"consistency", m.consistency},
                    {"sigma_px", m.sigma_px},
                    {"difference_px", m.difference_px}});
  return {
      {"verdict", v.verdict}, {"reason", v.reason}, {"grid", {v.columns, v.rows}}, {"maps", maps}};
}

void PrintValidation(const CalibrationValidation& v) {
  for (const MapValidation& m : v.maps) {
    std::printf("validation%s: uncertainty %.3f px at most (%.3f median)",
                m.distance_m > 0
                    ? (" at " + std::to_string(static_cast<int>(m.distance_m)) + " m").c_str()
                    : "",
                m.max_sigma_px, m.median_sigma_px);
    if (m.split)
      std::printf("; halves differ by %.3f px at most, %.2f of their sigmas", m.max_difference_px,
                  m.consistency);
    std::printf("\n");
  }
  std::printf("verdict: %s: %s\n", v.verdict.c_str(), v.reason.c_str());
}

// The report beside the calibration file; its directory.
std::string WriteReport(const CalibrationReport& report, const std::string& calibration_file) {
  const std::string dir = CalibrationReportDir(calibration_file);
  const Result<std::vector<std::string>> written = WriteCalibrationReport(report, dir);
  if (!written)
    throw CommandError("the calibration is written, its report is not: " + written.error());
  return dir;
}

void PrintCamera(const char* name, const CameraCalibration& c) {
  std::printf(
      "%s: %zu views, RMS %.3f px; c %.2f +- %.2f px, principal point %.2f %.2f (+- %.2f %.2f) "
      "px; %d of %d observations rejected; frame covered %.0f %% (edges %.0f %%)\n",
      name, c.view_rms_px.size(), c.rms_px, c.intrinsics.principal_distance_px, c.sigma[0], c.cx(),
      c.cy(), c.sigma[1], c.sigma[2], c.rejected, c.observations, 100.0 * c.coverage.share,
      100.0 * c.coverage.border_share);
  for (const std::string& term : c.fixed_insignificant)
    std::printf("  fixed at zero, not significant: %s\n", term.c_str());
  for (const std::string& pair : c.high_correlations)
    std::printf("  correlated parameters %s\n", pair.c_str());
  for (const std::string& w : c.warnings) std::printf("warning: %s: %s\n", name, w.c_str());
}

Result<CameraCalibration> CalibrateCameraFromBoards(const CalibrateArgs& args,
                                                    const std::vector<std::string>& files,
                                                    std::vector<std::string>* skipped,
                                                    TargetViews* detected) {
  const TargetViews& views = *detected = DetectBoards(files, args, skipped);
  Result<CameraCalibration> c = CalibrateCamera(views, args.options);
  if (!c)
    return Error{c.error() + " (" + std::to_string(views.views.size()) + " of " +
                 std::to_string(files.size()) + " images show the board)"};
  return c;
}

void RunCalibrateCamera(CalibrateArgs args) {
  args.board = ParseBoardFlags(args.board_flags);
  const std::vector<std::string> files = ExpandGlob("--images", args.images);
  std::vector<std::string> skipped;
  FieldReport field;
  Result<CameraCalibration> c = Error{""};
  TargetViews views;
  if (args.AtField()) {
    const FieldInputs in =
        LoadFieldInputs(args, {files}, {args.side == "right" ? Side::kRight : Side::kLeft});
    c = CalibrateCameraAtField(in.field, in.views, args.options, args.field, &field);
    if (c) views = field.views[0];
  } else {
    c = CalibrateCameraFromBoards(args, files, &skipped, &views);
  }
  if (!c) throw CommandError(c.error());
  const CalibrationValidation validation = ValidateCamera(*c, views, args.options, args.validation);
  const std::string yaml = CameraCalibrationToYaml(c->intrinsics, PrecisionOf(*c));
  if (Status s = WriteFileAtomically(args.out, yaml); !s) throw CommandError(s.error());
  nlohmann::json j = CameraJson(*c);
  j["views_skipped"] = skipped;
  if (args.AtField()) j["control_field"] = FieldJson(field);
  j["validation"] = ValidationJson(validation);
  j["out"] = args.out;
  j["report"] = WriteReport({j, {{"camera", &*c}}, &validation}, args.out);
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  if (args.AtField()) PrintFieldReport(field);
  PrintCamera("camera", *c);
  PrintValidation(validation);
  std::printf("written %s, report in %s\n", args.out.c_str(),
              j["report"].get<std::string>().c_str());
}

void RunCalibrateStereo(CalibrateArgs args) {
  args.board = ParseBoardFlags(args.board_flags);
  std::optional<Calibration> previous;  // read before the work that needs it
  if (!args.stage_from.empty()) {
    Result<Calibration> loaded = LoadCalibrationYaml(args.stage_from);
    if (!loaded) throw CommandError("--stage-from: " + loaded.error());
    previous = *loaded;
  }
  const std::vector<std::string> left_files = ExpandGlob("--left", args.left);
  const std::vector<std::string> right_files = ExpandGlob("--right", args.right);
  if (left_files.size() != right_files.size())
    throw CommandError("--right: " + std::to_string(right_files.size()) + " images, --left has " +
                       std::to_string(left_files.size()) +
                       ": the views are paired in sorted order");
  std::vector<std::string> skipped;
  FieldReport field;
  Result<StereoCalibration> s = Error{""};
  TargetViews left, right;
  if (args.AtField()) {
    const FieldInputs in =
        LoadFieldInputs(args, {left_files, right_files}, {Side::kLeft, Side::kRight});
    s = CalibrateStereoAtField(in.field, in.views, args.options, args.field, &field);
    if (s) left = field.views[0], right = field.views[1];
  } else {
    left = DetectBoards(left_files, args, &skipped);
    right = DetectBoards(right_files, args, &skipped);
    s = CalibrateStereo(left, right, args.options);
    if (!s)
      s = Error{s.error() + " (the board found in " + std::to_string(left.views.size()) +
                " left and " + std::to_string(right.views.size()) + " right images)"};
  }
  if (!s) throw CommandError(s.error());
  const CalibrationValidation validation =
      ValidateStereo(*s, left, right, args.options, args.validation);
  const Calibration cal = CalibrationOf(*s, previous);
  std::string why;
  if (!cal.Check(&why)) throw CommandError("the stereo calibration is not a valid rig: " + why);
  if (Status st = SaveCalibrationYaml(cal, args.out); !st) throw CommandError(st.error());
  const nlohmann::json stereo = {
      {"rms_px", s->rms_px},
      {"sigma0_px", s->sigma0_px},
      {"baseline", s->baseline},
      {"baseline_sigma", s->baseline_sigma},
      {"angles_deg", {s->angles_deg.x(), s->angles_deg.y(), s->angles_deg.z()}},
      {"angles_sigma_deg",
       {s->angles_sigma_deg.x(), s->angles_sigma_deg.y(), s->angles_sigma_deg.z()}},
      {"observations", s->observations},
      {"rejected", s->rejected}};
  nlohmann::json j = {
      {"left", CameraJson(s->left)}, {"right", CameraJson(s->right)}, {"stereo", stereo},
      {"views_skipped", skipped},    {"warnings", s->warnings},       {"out", args.out}};
  if (args.AtField()) j["control_field"] = FieldJson(field);
  j["validation"] = ValidationJson(validation);
  j["report"] = WriteReport({j, {{"left", &s->left}, {"right", &s->right}}, &validation}, args.out);
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  if (args.AtField()) PrintFieldReport(field);
  PrintCamera("left", s->left);
  PrintCamera("right", s->right);
  std::printf(
      "stereo: RMS %.3f px; baseline %.5f +- %.5f; omega phi kappa %.4f %.4f %.4f (+- %.4f %.4f "
      "%.4f) deg\n",
      s->rms_px, s->baseline, s->baseline_sigma, s->angles_deg.x(), s->angles_deg.y(),
      s->angles_deg.z(), s->angles_sigma_deg.x(), s->angles_sigma_deg.y(), s->angles_sigma_deg.z());
  PrintValidation(validation);
  std::printf("written %s, report in %s\n", args.out.c_str(),
              j["report"].get<std::string>().c_str());
}

struct OpenCvArgs {
  std::string calibration, camera, opencv, out;
};

void PrintConversion(const char* name, const ModelConversion& c) {
  std::printf("%s: the two lens models project the frame alike within %.4f px\n", name,
              c.max_difference_px);
  if (c.max_difference_px > c.tolerance_px)
    std::printf(
        "warning: %s: more than %.2f px apart at the frame's edge (decentring under "
        "strong distortion has no exact counterpart)\n",
        name, c.tolerance_px);
}

void RunExportOpenCv(const OpenCvArgs& args) {
  if (args.calibration.empty() == args.camera.empty())
    throw CommandError("export-opencv: give one of --calibration and --camera");
  if (!args.camera.empty()) {
    const Result<CameraIntrinsics> camera = LoadCameraCalibrationYaml(args.camera);
    if (!camera) throw CommandError(camera.error());
    ModelConversion conversion;
    if (Status s = SaveOpenCvCamera(*camera, args.out, &conversion); !s)
      throw CommandError(s.error());
    PrintConversion("camera", conversion);
  } else {
    const Result<Calibration> cal = LoadCalibrationYaml(args.calibration);
    if (!cal) throw CommandError(cal.error());
    OpenCvExport conversion;
    if (Status s = SaveOpenCvStereo(*cal, args.out, &conversion); !s) throw CommandError(s.error());
    PrintConversion("left", conversion.left);
    PrintConversion("right", conversion.right);
  }
  std::printf("written %s\n", args.out.c_str());
}

void RunImportOpenCv(const OpenCvArgs& args) {
  if (!args.camera.empty()) {
    ModelConversion conversion;
    const Result<CameraIntrinsics> camera = LoadOpenCvCamera(args.opencv, &conversion);
    if (!camera) throw CommandError(camera.error());
    if (Status s = WriteFileAtomically(args.camera, CameraCalibrationToYaml(*camera, {})); !s)
      throw CommandError(s.error());
    PrintConversion("camera", conversion);
    std::printf("written %s\n", args.camera.c_str());
    return;
  }
  if (args.out.empty()) throw CommandError("import-opencv: give --out or --camera");
  OpenCvExport conversion;
  const Result<Calibration> cal = LoadOpenCvStereo(args.opencv, &conversion);
  if (!cal) throw CommandError(cal.error());
  if (Status s = SaveCalibrationYaml(*cal, args.out); !s) throw CommandError(s.error());
  PrintConversion("left", conversion.left);
  PrintConversion("right", conversion.right);
  std::printf("written %s\n", args.out.c_str());
}

void AddOpenCvCommands(CLI::App* calibrate) {
  auto args = std::make_shared<OpenCvArgs>();
  CLI::App* out = calibrate->add_subcommand(
      "export-opencv",
      "Write a calibration as OpenCV FileStorage YAML (cameraMatrix, distCoeffs, "
      "R, T), the lens model converted");
  out->add_option("--calibration", args->calibration, "a stereo calibration (calibration.yaml)");
  out->add_option("--camera", args->camera, "or one camera's (calibrate camera --out)");
  out->add_option("--out", args->out, "OpenCV YAML to write")->required();
  out->callback([args] { RunExportOpenCv(*args); });
  CLI::App* in = calibrate->add_subcommand(
      "import-opencv",
      "Read an OpenCV FileStorage calibration (stereoCalibrate's or one camera's)");
  in->add_option("--opencv", args->opencv, "OpenCV YAML or XML to read")->required();
  in->add_option("--out", args->out, "stereo calibration (YAML) to write");
  in->add_option("--camera", args->camera, "or one camera's calibration to write");
  in->callback([args] { RunImportOpenCv(*args); });
}

void AddAdjustmentFlags(CLI::App* cmd, CalibrateArgs* args) {
  AddBoardFlags(cmd, &args->board_flags);
  cmd->add_option("--control-field", args->control_field,
                  "calibrate at a control field instead: its targets (FIELD.yaml)")
      ->excludes(args->board_flags.chessboard_flag)
      ->excludes(args->board_flags.charuco_flag)
      ->excludes(args->board_flags.circle_markers_flag);
  cmd->add_option("--marks", args->marks,
                  "with --control-field: targets measured by hand (MARKS.yaml), 4 or more in "
                  "each stage pose's left or right image");
  cmd->add_option("--start", args->start,
                  "with --control-field: the rig's design calibration (calibration.yaml)");
  AddDeclaredOption(cmd, "--search-px", args->field, "first_search_px");
  AddDeclaredOption(cmd, "--fix-principal-point", args->options, "fix_principal_point");
  AddDeclaredOption(cmd, "--fix-k3", args->options, "fix_k3");
  AddDeclaredOption(cmd, "--fix-tangential", args->options, "fix_tangential");
  AddDeclaredOption(cmd, "--fix-scale-x", args->options, "fix_scale_x");
  AddDeclaredOption(cmd, "--keep-all-terms", args->options, "keep_all_terms");
  AddDeclaredOption(cmd, "--significance-t", args->options, "significance_t");
  AddDeclaredOption(cmd, "--huber-px", args->options, "adjustment.huber_px");
  AddDeclaredOption(cmd, "--reject-k", args->options, "adjustment.rejection_k");
  AddDeclaredOption(cmd, "--rejection-rounds", args->options, "adjustment.max_rejection_rounds");
  cmd->add_flag("--json", args->json, "print the result as JSON");
}

}  // namespace

void AddCalibrateCommand(CLI::App& app) {
  CLI::App* calibrate = app.add_subcommand("calibrate", "Calibrate the cameras");
  calibrate->require_subcommand(1);
  auto camera_args = std::make_shared<CalibrateArgs>();
  CLI::App* camera = calibrate->add_subcommand(
      "camera", "One camera's interior orientation from chessboard views (Ceres adjustment)");
  camera->add_option("--images", camera_args->images, "the views, a glob ('cal/left*.png')")
      ->required();
  AddAdjustmentFlags(camera, camera_args.get());
  camera
      ->add_option("--side", camera_args->side,
                   "with --control-field: the design camera to start from")
      ->check(CLI::IsMember({"left", "right"}));
  camera->add_option("--out", camera_args->out, "camera calibration file (YAML) to write")
      ->required();
  camera->callback([camera_args] { RunCalibrateCamera(*camera_args); });

  auto stereo_args = std::make_shared<CalibrateArgs>();
  CLI::App* stereo = calibrate->add_subcommand(
      "stereo", "Both cameras and their relative orientation in one adjustment");
  stereo->add_option("--left", stereo_args->left, "the left views, a glob; paired in sorted order")
      ->required();
  stereo->add_option("--right", stereo_args->right, "the right views, a glob")->required();
  AddAdjustmentFlags(stereo, stereo_args.get());
  stereo->add_option("--stage-from", stereo_args->stage_from,
                     "keep the stage kinematics and the rig's roll from this calibration");
  stereo->add_option("--out", stereo_args->out, "calibration file (YAML) for process")->required();
  stereo->callback([stereo_args] { RunCalibrateStereo(*stereo_args); });
  AddOpenCvCommands(calibrate);
  AddCalibrateRigCommand(calibrate);
}

}  // namespace ts
