#include "sim/sim_station.h"

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <thread>

#include "processing/io/station_manifest.h"
#include "processing/matching/terrain_above_view.h"
#include "sim/noise.h"
#include "sim/truth.h"

namespace ts::sim {

bool SimStationOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (sun_deg.empty() || sun_deg.size() == 2) return true;
  if (why) *why = "sun must be AZIMUTH,ELEVATION (degrees)";
  return false;
}

bool StationRenderOptions::Check(std::string* why) const {
  return CheckDeclaredOptions(*this, why) && plan.Check(why);
}

Result<std::shared_ptr<const SimStation>> BuildSimStation(const SimStationOptions& options) {
  std::string why;
  if (!options.Check(&why)) return Error{"simulated station: " + why};
  Result<Scene> scene = options.dem_file.empty() ? MakeBuiltinScene(options.scene, options.seed)
                                                 : MakeSceneFromDem(options.dem_file, options.seed);
  if (!scene) return Error{scene.error()};
  auto station = std::make_shared<SimStation>();
  station->scene = std::move(*scene);
  if (station->scene.stage_height_m != options.stage_height_m) {
    // Re-level: the lattice was built for the default height.
    for (float& h : station->scene.heights)
      h -= static_cast<float>(options.stage_height_m - station->scene.stage_height_m);
    for (SceneObject& o : station->scene.objects) {
      const double dz = options.stage_height_m - station->scene.stage_height_m;
      o.ground.z() -= dz;
      o.canopy_centre.z() -= dz;
    }
    station->scene.stage_height_m = options.stage_height_m;
  }
  station->scene.epoch = options.epoch;
  for (const Subsidence& bowl : options.subsidence)
    if (Status s = ApplySubsidence(&station->scene, bowl); !s)
      return Error{"simulated station: " + s.error()};
  if (!options.sun_deg.empty())
    if (Status s = SetSun(&station->scene, options.sun_deg[0], options.sun_deg[1]); !s)
      return Error{"simulated station: " + s.error()};
  station->mesh = BuildSceneMesh(station->scene);
  station->rig = MakeSimRig(options.seed, options.stage_height_m);
  return std::shared_ptr<const SimStation>(std::move(station));
}

cv::Mat RenderRadiance(Renderer& renderer, const SimStation& station, const FrameRequest& r,
                       cv::Mat* range_m) {
  const CameraIntrinsics& intrinsics =
      r.side == Side::kLeft ? station.rig.truth.rig.left : station.rig.truth.rig.right;
  const Eigen::Isometry3d pose = station.rig.truth.LFromCamera(r.side, r.pan_deg, r.tilt_deg);
  return renderer.Render(CameraModel(intrinsics), pose, r.render, range_m);
}

cv::Mat ExposeFrame(const SimStation& station, const FrameRequest& r, const cv::Mat& radiance) {
  const CameraIntrinsics& intrinsics =
      r.side == Side::kLeft ? station.rig.truth.rig.left : station.rig.truth.rig.right;
  // Epoch 1 keeps the seed of the scene, so its images are those of every earlier version.
  const uint64_t epoch_seed = station.scene.epoch == 1
                                  ? station.scene.seed
                                  : Hash(station.scene.seed, 0xe90c, station.scene.epoch);
  uint64_t noise_seed = Hash(epoch_seed, r.side == Side::kLeft ? 1 : 2,
                             std::llround(r.pan_deg * 1e3), std::llround(r.tilt_deg * 1e3));
  if (r.view != 0) noise_seed = Hash(noise_seed, r.view, 0x71e);
  return ExposeImage(radiance, intrinsics, station.rig.sensor(r.side), r.exposure_us, r.gain_db,
                     r.format, noise_seed);
}

cv::Mat RenderFrame(Renderer& renderer, const SimStation& station, const FrameRequest& r,
                    cv::Mat* range_m) {
  return ExposeFrame(station, r, RenderRadiance(renderer, station, r, range_m));
}

namespace {

Status WritePair(const SimStation& station, const StationRenderOptions& o, Renderer renderers[2],
                 const std::string& dir, const std::string& truth_dir, int index,
                 const StagePose& commanded, double pan_deg, double tilt_deg,
                 StationManifest* manifest, cv::Mat images[2]) {
  PairRecord pair;
  pair.index = index;
  pair.commanded = commanded;
  // The encoder registers hold millidegrees.
  pair.readback = {std::round(pan_deg * 1e3) / 1e3, std::round(tilt_deg * 1e3) / 1e3};
  pair.inclinometer_deg = InclinometerReadsAt(station.rig, pair.readback.pan_deg) +
                          station.rig.inclinometer_noise_deg *
                              Eigen::Vector2d(HashGaussian(station.scene.seed, 0x1c13, index, 0),
                                              HashGaussian(station.scene.seed, 0x1c13, index, 1));
  pair.exposure_us = o.exposure_us;
  pair.gain_db = o.gain_db;
  pair.captured_utc = UtcNowIso8601();
  cv::Mat ranges[2];
  cv::Mat* range_out[2] = {o.write_range_images ? &ranges[0] : nullptr,
                           o.write_range_images ? &ranges[1] : nullptr};
  std::thread right([&] {
    images[1] =
        RenderFrame(renderers[1], station,
                    {Side::kRight, pan_deg, tilt_deg, o.exposure_us, o.gain_db, o.format, o.render},
                    range_out[1]);
  });
  images[0] = RenderFrame(
      renderers[0], station,
      {Side::kLeft, pan_deg, tilt_deg, o.exposure_us, o.gain_db, o.format, o.render}, range_out[0]);
  right.join();
  if (o.write_range_images) {
    for (Side side : {Side::kLeft, Side::kRight}) {
      char name[64];
      std::snprintf(name, sizeof(name), "range/pair_%02d_%s.tif", index, SideName(side));
      const std::string path = (std::filesystem::path(truth_dir) / name).string();
      if (!cv::imwrite(path, ranges[side == Side::kLeft ? 0 : 1]))
        return Error{path + ": cannot write range image"};
    }
  }
  for (Side side : {Side::kLeft, Side::kRight}) {
    ImageRecord& record = side == Side::kLeft ? pair.left : pair.right;
    record.file = StationManifest::ImageFileName(index, side);
    const Result<std::string> sha = WritePngAtomically(
        images[side == Side::kLeft ? 0 : 1], (std::filesystem::path(dir) / record.file).string());
    if (!sha) return Error{sha.error()};
    record.sha256 = *sha;
  }
  pair.left_timestamp_ns = pair.right_timestamp_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(
          std::chrono::system_clock::now().time_since_epoch())
          .count();
  manifest->pairs.push_back(pair);
  return SaveStationManifest(manifest, dir);  // the manifest commits the pair
}

}  // namespace

Status RenderStationDirectory(const SimStation& station, const StationRenderOptions& o,
                              const std::string& station_dir, const std::string& truth_dir,
                              const std::function<void(int, int)>& progress) {
  std::string why;
  if (!o.Check(&why)) return Error{"sim render: " + why};
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(station_dir) / "raw", ec);
  if (ec) return Error{station_dir + ": cannot create station directory: " + ec.message()};
  StationManifest manifest;
  manifest.station_id = "SIM-" + station.scene.name + "-" + std::to_string(station.scene.seed);
  manifest.software_version = "topostation sim render";
  manifest.rig_name = "simulated";
  manifest.calibration = station.rig.nominal;
  manifest.image_width_px = station.rig.nominal.rig.left.width_px;
  manifest.image_height_px = station.rig.nominal.rig.left.height_px;
  manifest.pixel_format = o.format;
  try {
    manifest.plan = MakeCapturePlan(station.rig.nominal, o.plan);
  } catch (const std::invalid_argument& e) {
    return Error{e.what()};
  }
  if (o.write_range_images) {
    std::filesystem::create_directories(std::filesystem::path(truth_dir) / "range", ec);
    if (ec) return Error{truth_dir + ": cannot create range folder: " + ec.message()};
  }
  nlohmann::json true_poses = nlohmann::json::array();
  std::mt19937_64 rng(Hash(station.scene.seed, 0xe7c0de, 0));
  std::normal_distribution<double> encoder(0.0, o.encoder_noise_deg);
  Renderer renderers[2] = {Renderer(station.scene, station.mesh),
                           Renderer(station.scene, station.mesh)};
  // The plan grows where the terrain goes on above a view (the capture's rule); the upper
  // poses come after the row. Judged as a calibrated rig would: with the true calibration (the
  // design values put far ground tens of per cent off in range).
  const Rectification rectification = Rectify(station.rig.truth.rig);
  for (int i = 0; i < static_cast<int>(manifest.plan.size()); ++i) {
    const StagePose p = manifest.plan[i];
    const double pan = p.pan_deg + encoder(rng), tilt = p.tilt_deg + encoder(rng);
    true_poses.push_back({{"pan_deg", pan}, {"tilt_deg", tilt}});
    cv::Mat images[2];
    if (Status s = WritePair(station, o, renderers, station_dir, truth_dir, i, p, pan, tilt,
                             &manifest, images);
        !s)
      return s;
    ExtendPlanUpwards(station.rig.truth, rectification, images[0], images[1], p,
                      manifest.pairs.back().readback, o.plan, &manifest.plan);
    if (progress) progress(i + 1, static_cast<int>(manifest.plan.size()));
  }
  nlohmann::json plan = nlohmann::json::array();
  for (const StagePose& p : manifest.plan)
    plan.push_back({{"pan_deg", p.pan_deg}, {"tilt_deg", p.tilt_deg}});
  return WriteTruthDirectory(
      station.scene, station.rig, truth_dir,
      {{"capture_plan", plan}, {"true_poses", true_poses}, {"station_dir", station_dir}});
}

}  // namespace ts::sim
