#include "station/sim_station_options.h"

#include <string>
#include <vector>

#include "station/option_flags.h"

namespace ts {

void AddSimStationOptions(CLI::App* cmd, sim::SimStationOptions* options) {
  std::string scenes;
  for (const std::string& name : sim::BuiltinSceneNames())
    scenes += (scenes.empty() ? "" : ", ") + name;
  AddDeclaredOption(cmd, "--scene", *options, "scene")
      ->description("built-in scene: " + scenes + " (default " + options->scene + ")");
  AddDeclaredOption(cmd, "--dem", *options, "dem_file");
  AddDeclaredOption(cmd, "--seed", *options, "seed");
  AddDeclaredOption(cmd, "--height-m", *options, "stage_height_m");
  AddDeclaredOption(cmd, "--epoch", *options, "epoch");
  cmd->add_option_function<std::vector<double>>(
         "--subsidence",
         [options](const std::vector<double>& v) {
           if (v.size() % 4 != 0)
             throw CLI::ValidationError("--subsidence",
                                        "needs X,Y,RADIUS,DEPTH (m, station frame) per bowl");
           for (size_t i = 0; i < v.size(); i += 4) {
             sim::Subsidence bowl;
             bowl.centre_m = {v[i], v[i + 1]};
             bowl.radius_m = v[i + 2];
             bowl.depth_m = v[i + 3];
             options->subsidence.push_back(bowl);
           }
         },
         "a subsidence bowl since epoch 1: X,Y,RADIUS,DEPTH in m (repeatable)")
      ->delimiter(',');
  cmd->add_option("--sun", options->sun_deg,
                  "sun AZIMUTH,ELEVATION in degrees (default: the scene's sun)")
      ->delimiter(',')
      ->expected(2);
}

}  // namespace ts
