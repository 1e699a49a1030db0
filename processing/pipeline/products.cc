#include "processing/pipeline/products.h"

#include <cmath>
#include <filesystem>
#include <future>

#include "processing/gravity/terrain_correction_json.h"
#include "processing/io/atomic_file.h"
#include "processing/io/image_file.h"
#include "processing/io/point_cloud_file.h"
#include "processing/io/raster.h"
#include "processing/products/dem_image.h"

namespace ts {
namespace {

// points.ply: every point in the DEM's frame with its sigmas, pair, correlation and class.
Status WritePoints(const StationWork& w, const std::string& file) {
  const PointCloud& cloud = w.cloud;
  const std::optional<Georeference>& georeference = w.inputs->georeference;
  std::vector<Eigen::Vector3d> xyz(cloud.size());
  PlyColumn sigma{"sigma", {}, {}, {}}, sigma_z{"sigma_z", {}, {}, {}};
  PlyColumn pair{"pair", {}, {}, {}}, correlation{"correlation", {}, {}, {}};
  PlyColumn ground_flag{"ground", {}, {}, {}}, classification{"class", {}, {}, {}};
  for (size_t i = 0; i < cloud.size(); ++i) {
    xyz[i] = georeference ? georeference->ToWorld(cloud[i].position_m) : cloud[i].position_m;
    sigma.f32.push_back(std::sqrt(cloud[i].covariance_m2.trace()));
    sigma_z.f32.push_back(std::sqrt(cloud[i].covariance_m2(2, 2)));
    pair.i32.push_back(cloud[i].pair);
    correlation.f32.push_back(cloud[i].correlation);
    ground_flag.u8.push_back(w.point_class[i] == kGround);
    classification.u8.push_back(w.point_class[i]);
  }
  return WritePly(file, xyz, {sigma, sigma_z, pair, correlation, ground_flag, classification});
}

}  // namespace

bool WriteProducts(const ProcessOptions& o, const StationWork& w, StepSummary* s) {
  const std::string products = w.inputs->dir + "/products";
  std::error_code ec;
  std::filesystem::create_directories(products, ec);
  if (ec) {
    s->message = products + ": cannot create (" + ec.message() + ")";
    return false;
  }
  // The cloud and the pictures are written on threads of their own while the rasters are:
  // the products are what the operator waits for after the last pair.
  auto points =
      std::async(std::launch::async, [&] { return WritePoints(w, products + "/points.ply"); });
  auto pictures = std::async(std::launch::async, [&]() -> Status {
    auto dem_png =
        WritePngAtomically(RenderDemImage(w.kriged.dem, w.station_xy), products + "/dem.png");
    if (!dem_png) return Error{dem_png.error()};
    auto panorama = WritePngAtomically(w.panorama, products + "/panorama.png");
    if (!panorama) return Error{panorama.error()};
    if (!w.seams_image.empty()) {
      auto seams = WritePngAtomically(w.seams_image, products + "/seams.png");
      if (!seams) return Error{seams.error()};
    }
    return {};
  });
  Status written = WriteGeoTiff(w.kriged.dem, products + "/dem.tif");
  if (written) written = WriteGeoTiff(w.kriged.std, products + "/dem_std.tif");
  if (written) written = WriteGeoTiff(w.ceilings.per_cell, products + "/dem_ceiling.tif");
  if (written)
    written = WriteFileAtomically(
        products + "/terrain_correction.json",
        TerrainCorrectionToJson(w.terrain_correction, o.terrain_correction, w.mark_dem).dump(2) +
            "\n");
  for (auto* job : {&points, &pictures}) {
    Status done = job->get();
    if (written) written = done;
  }
  if (!written) s->message = written.error();
  return written.ok();
}

}  // namespace ts
