#include "processing/pipeline/process_options.h"

namespace ts {

bool ProcessOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!rig_ties.Check(&err))
    err = "rig tie points: " + err;
  else if (!rig_adjustment.Check(&err))
    err = "rig adjustment: " + err;
  else if (!matching.Check(&err))
    err = "matching: " + err;
  else if (!blunders.Check(&err))
    err = "blunder filter: " + err;
  else if (!sight_lines.Check(&err))
    err = "sight-line objects: " + err;
  else if (!ground.Check(&err))
    err = "ground filter: " + err;
  else if (!underside_patches.Check(&err))
    err = "underside patches: " + err;
  else if (!kriging.Check(&err))
    err = "kriging: " + err;
  else if (!horizon.Check(&err))
    err = "horizon: " + err;
  else if (!panorama.Check(&err))
    err = "panorama: " + err;
  else if (!terrain_correction.Check(&err))
    err = "terrain correction: " + err;
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

nlohmann::json ProcessOptionsToJson(const ProcessOptions& options) {
  return DeclaredOptionsToJson(options);
}

}  // namespace ts
