#include "processing/gravity/terrain_correction_json.h"

#include <cmath>

namespace ts {

nlohmann::json TerrainCorrectionToJson(const TerrainCorrection& tc,
                                       const TerrainCorrectionOptions& o,
                                       const Eigen::Vector3d& mark) {
  nlohmann::json rings = nlohmann::json::array();
  for (const RingContribution& r : tc.rings) {
    nlohmann::json sectors = nlohmann::json::array();
    for (const SectorContribution& s : r.sectors)
      sectors.push_back({{"bearing_deg", s.bearing_deg},
                         {"coverage", s.coverage},
                         {"seen", s.seen},
                         {"sigma_mgal", s.sigma_mgal}});
    rings.push_back({{"inner_m", r.inner_m},
                     {"outer_m", std::isinf(r.outer_m) ? nlohmann::json("end of DEM")
                                                       : nlohmann::json(r.outer_m)},
                     {"mgal", r.mgal},
                     {"coverage", r.coverage},
                     {"sigma_mgal", r.sigma_mgal},
                     {"sigma_unseen_mgal", r.sigma_unseen_mgal},
                     {"sectors", sectors}});
  }
  // An unusable correction has no value: null, with the reason, never a number to copy.
  auto value = [&](double v) { return tc.Usable() ? nlohmann::json(v) : nlohmann::json(); };
  return {
      {"terrain_correction_mgal", value(tc.total_mgal)},
      {"sigma_mgal", value(tc.sigma_mgal)},
      {"verdict", tc.Usable() ? "usable" : "unusable"},
      {"unusable_because", tc.Usable() ? nlohmann::json() : nlohmann::json(tc.unusable_because)},
      {"sigma_unseen_mgal", tc.sigma_unseen_mgal},
      {"sigma_fully_correlated_mgal", tc.sigma_correlated_mgal},
      {"sigma_method",
       "per cell, the std of its prism's correction over its height +- its std (Gauss-Hermite, "
       "not linearised: near the mark's height the correction is quadratic); cells whose ground "
       "was seen "
       "independent, cells nobody saw (bounded by the lines of sight and how the seen "
       "ground turns) as one unknown, added linearly; the fully correlated sum is an upper "
       "bound"},
      {"rings", rings},
      {"quadrants_mgal",
       {{"NE", tc.quadrant_mgal[0]},
        {"SE", tc.quadrant_mgal[1]},
        {"SW", tc.quadrant_mgal[2]},
        {"NW", tc.quadrant_mgal[3]}}},
      {"station_mark", {mark.x(), mark.y(), mark.z()}},
      {"dem_misfit_at_mark_m", tc.station_misfit_m},
      {"density_g_cm3", o.density_kg_m3 / 1000.0},
      {"sensor_height_m", o.sensor_height_m},
      {"radius_m", o.radius_m > 0 ? nlohmann::json(o.radius_m) : nlohmann::json("whole DEM")},
      {"warnings", tc.warnings}};
}

}  // namespace ts
