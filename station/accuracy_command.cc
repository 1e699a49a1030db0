// topostation accuracy --rig RIG.yaml: theoretical mapping accuracy against range (seed 003
// eq. 1) as a table, a PNG plot and, with --json, {"rows": [...]}.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "acquisition/rig_config.h"
#include "processing/geometry/theoretical_accuracy.h"
#include "station/accuracy_plot.h"
#include "station/commands.h"
#include "station/option_flags.h"

namespace ts {
namespace {

struct AccuracyArgs {
  std::string rig_file;
  std::string plot_png = "accuracy.png";
  bool json = false;
  TheoreticalAccuracyOptions options;
  bool at_centre = false;
};

void PrintTable(const std::vector<AccuracyRow>& rows, const std::string& rig_name, double f_px,
                double baseline_m, const TheoreticalAccuracyOptions& o) {
  std::printf("Theoretical accuracy of rig '%s' (seed 003 eq. 1)\n", rig_name.c_str());
  std::printf(
      "B = %.3f m, f = %.1f px, sigma_p = %.3f px, point at (%.0f, %.0f) px from the "
      "principal point\n\n",
      baseline_m, f_px, o.sigma_parallax_px, o.image_x_px, o.image_y_px);
  std::printf("%9s %11s %11s %11s\n", "range_m", "sigma_x_m", "sigma_y_m", "sigma_z_m");
  for (const AccuracyRow& r : rows)
    std::printf("%9.1f %11.3f %11.3f %11.3f\n", r.range_m, r.sigma_x_m, r.sigma_y_m, r.sigma_z_m);
}

void Run(const AccuracyArgs& args) {
  const Result<RigConfig> rig = LoadRigConfig(args.rig_file);
  if (!rig) throw CommandError(rig.error());
  const StereoRig& stereo = rig->calibration.rig;
  const double f_px =
      0.5 * (stereo.left.principal_distance_px + stereo.right.principal_distance_px);
  TheoreticalAccuracyOptions o = args.options;
  if (!args.at_centre) {  // worst case: the image corner farthest from the principal point
    const CameraIntrinsics& c = stereo.left;
    o.image_x_px = std::max(c.principal_point_x_px, c.width_px - 1 - c.principal_point_x_px);
    o.image_y_px = std::max(c.principal_point_y_px, c.height_px - 1 - c.principal_point_y_px);
  }
  o.sigma_image_px = o.sigma_parallax_px;
  std::string why;
  if (!o.Check(&why)) throw CommandError("accuracy: " + why);
  const std::vector<AccuracyRow> rows = TheoreticalAccuracy(stereo.baseline_m, f_px, o);
  if (!args.plot_png.empty()) {
    const Status s =
        WriteAccuracyPlot(rows, "Theoretical accuracy, rig " + rig->name, args.plot_png);
    if (!s) throw CommandError(s.error());
  }
  if (args.json) {
    nlohmann::json out = {{"rig", rig->name},
                          {"baseline_m", stereo.baseline_m},
                          {"principal_distance_px", f_px},
                          {"sigma_parallax_px", o.sigma_parallax_px},
                          {"image_x_px", o.image_x_px},
                          {"image_y_px", o.image_y_px},
                          {"plot_png", args.plot_png},
                          {"rows", nlohmann::json::array()}};
    for (const AccuracyRow& r : rows)
      out["rows"].push_back({{"range_m", r.range_m},
                             {"sigma_x_m", r.sigma_x_m},
                             {"sigma_y_m", r.sigma_y_m},
                             {"sigma_z_m", r.sigma_z_m}});
    std::cout << out.dump(2) << "\n";
    return;
  }
  PrintTable(rows, rig->name, f_px, stereo.baseline_m, o);
  if (!args.plot_png.empty()) std::printf("\nplot: %s\n", args.plot_png.c_str());
}

}  // namespace

void AddAccuracyCommand(CLI::App& app) {
  auto args = std::make_shared<AccuracyArgs>();
  CLI::App* cmd = app.add_subcommand(
      "accuracy", "Theoretical accuracy (sigma X, Y, Z) against range for a rig, seed 003 eq. 1");
  cmd->add_option("--rig", args->rig_file, "rig config (YAML)")->required();
  AddDeclaredOption(cmd, "--sigma-px", args->options, "sigma_parallax_px");
  AddDeclaredOption(cmd, "--min-range-m", args->options, "range_min_m");
  AddDeclaredOption(cmd, "--max-range-m", args->options, "range_max_m");
  AddDeclaredOption(cmd, "--step-m", args->options, "range_step_m");
  cmd->add_flag("--at-centre", args->at_centre,
                "point at the principal point instead of the image corner (worst case)");
  cmd->add_option("--plot", args->plot_png, "PNG plot to write ('' for none)")
      ->default_str("accuracy.png");
  cmd->add_flag("--json", args->json, "print JSON instead of the table");
  cmd->callback([args] { Run(*args); });
}

}  // namespace ts
