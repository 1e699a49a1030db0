#include "station/sim_station_options.h"

#include <string>
#include <vector>

namespace ts {

void AddSimStationOptions(CLI::App* cmd, sim::SimStationOptions* options) {
  cmd->add_option("--scene", options->scene,
                  "built-in scene: flat, hills, slope, rough, forest (default hills)");
  cmd->add_option("--dem", options->dem_file, "GeoTIFF DEM as terrain instead of a scene");
  cmd->add_option("--seed", options->seed, "scene and rig seed (default 1)");
  cmd->add_option("--height-m", options->stage_height_m,
                  "stage centre above the station mark (default 1.5)");
  cmd->add_option("--epoch", options->epoch,
                  "survey epoch of the same site (default 1; later epochs get new sensor noise)");
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
