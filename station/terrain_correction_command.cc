// topostation terrain-correction (STATION | DEM.tif): the near-region terrain correction of
// the gravity reading at the station, in mGal with its standard deviation (DESIGN.md).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/options.h"
#include "processing/gravity/terrain_correction_json.h"
#include "processing/io/atomic_file.h"
#include "processing/io/raster.h"
#include "station/commands.h"
#include "station/dem_input.h"
#include "station/option_flags.h"

namespace ts {
namespace {

struct TerrainCorrectionArgs {
  std::string input;
  std::vector<double> station_xy;
  double station_z = NAN;
  TerrainCorrectionOptions options;
  double density_g_cm3 = options.density_kg_m3 / 1000.0;  // the unit gravimetrists use
  std::string out;
  bool json = false;
};

// A station's products are `process`'s (its terrain correction counts the ground nobody saw,
// which a bare DEM cannot say): a DEM inside STATION/products/ is not written beside.
bool InStationProducts(const std::string& dem_file) {
  const std::filesystem::path dir = std::filesystem::absolute(dem_file).parent_path();
  return dir.filename() == "products" &&
         std::filesystem::exists(dir.parent_path() / "station.json");
}

void Run(const TerrainCorrectionArgs& args) {
  const DemInput in = LoadDemInput(args.input);
  const Raster& dem = in.dem;
  Eigen::Vector3d mark;
  if (in.station_mark && args.station_xy.empty()) {
    mark = *in.station_mark;
  } else {
    if (args.station_xy.size() != 2)
      throw CommandError(in.dem_file + ": a bare DEM needs --station X,Y (the mark's position)");
    mark.x() = args.station_xy[0], mark.y() = args.station_xy[1];
    if (!mark.head<2>().allFinite() || std::isinf(args.station_z))
      throw CommandError("terrain-correction: --station and --station-z must be finite numbers");
    if (args.station_z > kHighestGroundM || args.station_z < kLowestGroundM)
      throw CommandError("terrain-correction: --station-z " + OptionNumberText(args.station_z) +
                         " m is a height no ground has");
    mark.z() = std::isfinite(args.station_z) ? args.station_z : dem.Interpolate(mark.x(), mark.y());
    if (!std::isfinite(mark.z()))
      throw CommandError(in.dem_file + ": no height at the station " + std::to_string(mark.x()) +
                         ", " + std::to_string(mark.y()) +
                         " (outside or nodata; give --station-z)");
  }
  TerrainCorrectionOptions o = args.options;
  o.density_kg_m3 = args.density_g_cm3 * 1000.0;
  std::string why;
  if (!o.Check(&why)) throw CommandError("terrain-correction: " + why);
  const TerrainCorrection tc =
      ComputeTerrainCorrection(dem, in.std_dev ? &*in.std_dev : nullptr, mark, o);
  const nlohmann::json j = TerrainCorrectionToJson(tc, o, mark);
  const std::string out =
      !args.out.empty() ? args.out
      : in.station_dir || InStationProducts(in.dem_file)
          ? std::string()
          : std::filesystem::path(in.dem_file).replace_filename("terrain_correction.json").string();
  if (!out.empty())
    if (Status s = WriteFileAtomically(out, j.dump(2) + "\n"); !s) throw CommandError(s.error());
  if (args.json) {
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  if (!tc.Usable()) {
    std::printf("terrain correction unusable: %s\n", tc.unusable_because.c_str());
    return;
  }
  std::printf(
      "terrain correction %.4f +- %.4f mGal (density %.2f g/cm3, sensor %.2f m above the "
      "mark); %s\n",
      tc.total_mgal, tc.sigma_mgal, args.density_g_cm3, o.sensor_height_m,
      out.empty() ? "not written into the station (give --out)" : out.c_str());
  for (const RingContribution& r : tc.rings)
    if (r.coverage > 0.0)
      std::printf(
          "  ring %4.0f-%-4s m: %8.4f mGal, coverage %5.1f %%\n", r.inner_m,
          std::isinf(r.outer_m) ? "end" : std::to_string(static_cast<int>(r.outer_m)).c_str(),
          r.mgal, 100 * r.coverage);
  for (const std::string& w : tc.warnings) std::printf("warning: %s\n", w.c_str());
}

}  // namespace

void AddTerrainCorrectionCommand(CLI::App& app) {
  auto args = std::make_shared<TerrainCorrectionArgs>();
  CLI::App* t =
      app.add_subcommand("terrain-correction",
                         "Near-region terrain correction (mGal) from a station or a DEM GeoTIFF");
  t->add_option("input", args->input, "processed station directory or DEM GeoTIFF")->required();
  t->add_option("--station", args->station_xy, "X,Y of the station mark (bare DEM)")
      ->delimiter(',');
  t->add_option("--station-z", args->station_z, "height of the mark (default: from the DEM)");
  AddDeclaredOption(t, "--sensor-height", args->options, "sensor_height_m");
  std::ostringstream density;
  density << "density of the terrain (g/cm3, default " << args->density_g_cm3 << ")";
  t->add_option("--density", args->density_g_cm3, density.str());
  AddDeclaredOption(t, "--radius", args->options, "radius_m");
  t->add_option("--out", args->out,
                "JSON file (default: terrain_correction.json beside a bare DEM; none for a "
                "station's, whose products are process's)");
  t->add_flag("--json", args->json, "print the result as JSON");
  t->callback([args] { Run(*args); });
}

}  // namespace ts
