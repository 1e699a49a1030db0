#include "sim/truth.h"

#include <filesystem>

#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"

namespace ts::sim {
namespace {

template <typename Fn>
Raster SampleGrid(const Scene& scene, double cell_m, Fn value) {
  const int cells = static_cast<int>(std::lround(2.0 * scene.half_extent_m / cell_m));
  Raster r = Raster::Make(-scene.half_extent_m, scene.half_extent_m, cell_m, cells, cells);
  for (int row = 0; row < cells; ++row)
    for (int col = 0; col < cells; ++col)
      r.at(row, col) = static_cast<float>(value(r.CellCentreX(col), r.CellCentreY(row)));
  return r;
}

}  // namespace

Raster SampleTerrain(const Scene& scene, double cell_m) {
  return SampleGrid(scene, cell_m, [&](double x, double y) { return scene.TerrainHeight(x, y); });
}

Raster SampleObjectMask(const Scene& scene, double cell_m) {
  return SampleGrid(scene, cell_m,
                    [&](double x, double y) { return scene.ObjectCovers(x, y) ? 1.0 : 0.0; });
}

Status WriteTruthDirectory(const Scene& scene, const SimRig& rig, const std::string& dir,
                           const nlohmann::json& extra) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{dir + ": cannot create truth directory: " + ec.message()};
  const std::filesystem::path d(dir);
  if (Status s = WriteGeoTiff(SampleTerrain(scene, 1.0), (d / "dem.tif").string()); !s) return s;
  if (Status s = WriteGeoTiff(SampleTerrain(scene, 0.25), (d / "dem_fine.tif").string()); !s)
    return s;
  const Raster mask = SampleObjectMask(scene, 0.25);
  if (Status s = WriteGeoTiff(mask, (d / "objects.tif").string()); !s) return s;
  if (Status s = SaveCalibrationYaml(rig.truth, (d / "calibration.yaml").string()); !s) return s;

  double covered = 0.0;
  for (float v : mask.values) covered += v;
  int trees = 0, bushes = 0;
  for (const SceneObject& o : scene.objects) (o.kind == ObjectKind::kTree ? trees : bushes)++;
  nlohmann::json truth = {
      {"schema", "topostation.sim-truth"},
      {"schema_version", 1},
      {"scene", scene.name},
      {"seed", scene.seed},
      {"frame", "station frame L: origin at the stage centre, Z up, Y = pan 0"},
      {"stage_height_m", scene.stage_height_m},
      {"station_mark_l", {0.0, 0.0, -scene.stage_height_m}},
      {"extent_m", 2.0 * scene.half_extent_m},
      {"sun_direction_l",
       {scene.lighting.to_sun.x(), scene.lighting.to_sun.y(), scene.lighting.to_sun.z()}},
      {"trees", trees},
      {"bushes", bushes},
      {"object_cover_fraction", covered / mask.values.size()},
      {"inclinometer_deg", {rig.inclinometer_x_deg, rig.inclinometer_y_deg}},  // at home
      {"inclinometer_index_error_deg",
       {rig.inclinometer_index_error_deg.x(), rig.inclinometer_index_error_deg.y()}},
      {"files",
       {{"dem", "dem.tif"},
        {"dem_fine", "dem_fine.tif"},
        {"objects", "objects.tif"},
        {"calibration", "calibration.yaml"}}}};
  truth["epoch"] = scene.epoch;
  if (!scene.subsidence.empty()) {
    // The true change since epoch 1, both in closed form and as the rendered (triangulated
    // lattice) surface has it: the sum of the node lowerings times the node area.
    nlohmann::json bowls = nlohmann::json::array();
    for (const Subsidence& b : scene.subsidence) {
      double lattice_volume = 0.0;
      for (int iy = 0; iy < scene.n; ++iy)
        for (int ix = 0; ix < scene.n; ++ix)
          lattice_volume += b.LoweringAt(scene.LatticeX(ix), scene.LatticeX(iy));
      lattice_volume *= scene.spacing_m * scene.spacing_m;
      bowls.push_back({{"centre_l", {b.centre_m.x(), b.centre_m.y()}},
                       {"radius_m", b.radius_m},
                       {"max_depth_m", b.depth_m},
                       {"volume_m3", lattice_volume},
                       {"volume_closed_form_m3", b.Volume()},
                       {"profile", "depth * (1 + cos(pi r / radius)) / 2"}});
    }
    truth["subsidence"] = bowls;
  }
  if (extra.is_object()) truth.update(extra);
  return WriteFileAtomically((d / "truth.json").string(), truth.dump(2) + "\n");
}

}  // namespace ts::sim
