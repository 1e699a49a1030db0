// A scene whose terrain is any GeoTIFF DEM (GDAL), centred on the DEM's centre.
#include <cmath>

#include "processing/io/raster.h"
#include "sim/scene.h"

namespace ts::sim {

Result<Scene> MakeSceneFromDem(const std::string& dem_file, uint64_t seed) {
  Result<Raster> dem = ReadGeoTiff(dem_file);
  if (!dem) return Error{dem.error()};
  const double width = dem->cols * dem->cell_m, height = dem->rows * dem->cell_m;
  // The station and its 60 m square must be inside; the scene takes up to 120 m.
  const double half = std::floor(std::min({width, height, 121.0}) / 2.0 - dem->cell_m);
  if (half < 31.0)
    return Error{dem_file + ": DEM covers " + std::to_string(width) + " x " +
                 std::to_string(height) + " m; the scene needs at least 64 x 64 m"};
  const double cx = dem->min_x_m + width / 2.0, cy = dem->max_y_m - height / 2.0;
  if (std::isnan(dem->Interpolate(cx, cy)))
    return Error{dem_file + ": no data at the DEM centre (the station)"};
  Scene scene;
  scene.name = "dem:" + dem_file;
  scene.seed = seed;
  scene.half_extent_m = half;
  bool holes = false;
  FillLattice(&scene, [&](double x, double y) {
    const double z = dem->Interpolate(cx + x, cy + y);
    holes = holes || std::isnan(z);
    return z;
  });
  if (holes)
    return Error{dem_file + ": nodata within " + std::to_string(half) + " m of the centre"};
  return scene;
}

}  // namespace ts::sim
