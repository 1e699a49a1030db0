// topostation calibrate camera: one camera's interior orientation from chessboard views
// (issue 20, part 1 of the calibration commands).
#include <glob.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/log.h"
#include "processing/calibration/camera_calibration.h"
#include "processing/calibration/chessboard.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "station/commands.h"
#include "station/option_flags.h"

namespace ts {
namespace {

struct CalibrateCameraArgs {
  std::string images;
  std::string board_size = "9x6";
  ChessboardOptions board;
  CameraCalibrationOptions options;
  std::string out;
  bool json = false;
};

std::vector<std::string> ExpandGlob(const std::string& pattern) {
  glob_t matches{};
  std::vector<std::string> files;
  if (::glob(pattern.c_str(), 0, nullptr, &matches) == 0)
    for (size_t i = 0; i < matches.gl_pathc; ++i) files.emplace_back(matches.gl_pathv[i]);
  ::globfree(&matches);
  return files;
}

// The board in every image; an image without it is named in the log and skipped.
PlanarViews DetectBoards(const std::vector<std::string>& files, const ChessboardOptions& board,
                         cv::Size* size, std::vector<std::string>* skipped) {
  PlanarViews views;
  views.target = ChessboardCorners(board);
  for (const std::string& file : files) {
    const cv::Mat grey = cv::imread(file, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw CommandError(file + ": not a readable image");
    if (size->area() == 0) *size = grey.size();
    if (grey.size() != *size)
      throw CommandError(file + ": " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                         " pixels, the first image has " + std::to_string(size->width) + "x" +
                         std::to_string(size->height));
    if (auto corners = DetectChessboard(grey, board)) {
      views.names.push_back(std::filesystem::path(file).filename().string());
      views.pixels.push_back(*corners);
    } else {
      skipped->push_back(file);
      Log().warn("{}: no {}x{} chessboard found; view skipped", file, board.columns, board.rows);
    }
  }
  return views;
}

nlohmann::json ResultJson(const CameraCalibration& c, const std::vector<std::string>& skipped,
                          const std::string& out) {
  nlohmann::json sigma = nlohmann::json::object();
  for (int i = 0; i < CameraIntrinsics::kNumParameters; ++i)
    sigma[CameraIntrinsics::kParameterNames[i]] = c.sigma[i];
  return {{"rms_px", c.rms_px},
          {"sigma0_px", c.sigma0_px},
          {"fx", c.fx()},
          {"fy", c.fy()},
          {"cx", c.cx()},
          {"cy", c.cy()},
          {"k1", c.intrinsics.k1},
          {"k2", c.intrinsics.k2},
          {"k3", c.intrinsics.k3},
          {"p1", c.intrinsics.p1},
          {"p2", c.intrinsics.p2},
          {"scale_x", c.intrinsics.scale_x},
          {"shear", c.intrinsics.shear},
          {"sigma", sigma},
          {"high_correlations", c.high_correlations},
          {"views_used", c.view_rms_px.size()},
          {"views_skipped", skipped},
          {"view_rms_px", c.view_rms_px},
          {"observations", c.observations},
          {"out", out}};
}

void RunCalibrateCamera(CalibrateCameraArgs args) {
  if (!ParseBoardSize(args.board_size, &args.board))
    throw CommandError("--chessboard: expected COLUMNSxROWS of inner corners, e.g. 9x6, got '" +
                       args.board_size + "'");
  std::string why;
  if (!args.board.Check(&why)) throw CommandError("--chessboard: " + why);
  const std::vector<std::string> files = ExpandGlob(args.images);
  if (files.empty()) throw CommandError("--images: no file matches '" + args.images + "'");
  cv::Size size;
  std::vector<std::string> skipped;
  const PlanarViews views = DetectBoards(files, args.board, &size, &skipped);
  const Result<CameraCalibration> c = CalibrateCamera(views, size.width, size.height, args.options);
  if (!c)
    throw CommandError(c.error() + " (" + std::to_string(views.pixels.size()) + " of " +
                       std::to_string(files.size()) + " images show the board)");
  const std::string yaml = CameraCalibrationToYaml(c->intrinsics, c->sigma, c->rms_px);
  if (Status s = WriteFileAtomically(args.out, yaml); !s) throw CommandError(s.error());
  if (args.json) {
    std::printf("%s\n", ResultJson(*c, skipped, args.out).dump().c_str());
    return;
  }
  std::printf(
      "%zu of %zu views: RMS %.3f px; c %.2f +- %.2f px, principal point %.2f %.2f "
      "(+- %.2f %.2f) px; %s\n",
      views.pixels.size(), files.size(), c->rms_px, c->intrinsics.principal_distance_px,
      c->sigma[0], c->cx(), c->cy(), c->sigma[1], c->sigma[2], args.out.c_str());
  for (const std::string& pair : c->high_correlations)
    std::printf("warning: correlated parameters %s\n", pair.c_str());
}

}  // namespace

void AddCalibrateCommand(CLI::App& app) {
  CLI::App* calibrate = app.add_subcommand("calibrate", "Calibrate the cameras");
  calibrate->require_subcommand(1);
  auto args = std::make_shared<CalibrateCameraArgs>();
  CLI::App* camera = calibrate->add_subcommand(
      "camera", "One camera's interior orientation from chessboard views (Ceres adjustment)");
  camera->add_option("--images", args->images, "the views, a glob ('cal/left*.png')")->required();
  camera->add_option("--chessboard", args->board_size,
                     "inner corners COLUMNSxROWS (default " + args->board_size + ")");
  AddDeclaredOption(camera, "--square", args->board, "square");
  AddDeclaredOption(camera, "--fix-k3", args->options, "fix_k3");
  AddDeclaredOption(camera, "--fix-tangential", args->options, "fix_tangential");
  AddDeclaredOption(camera, "--fix-scale-x", args->options, "fix_scale_x");
  AddDeclaredOption(camera, "--huber-px", args->options, "huber_px");
  camera->add_option("--out", args->out, "camera calibration file (YAML) to write")->required();
  camera->add_flag("--json", args->json, "print the result as JSON");
  camera->callback([args] { RunCalibrateCamera(*args); });
}

}  // namespace ts
