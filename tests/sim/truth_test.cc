#include "sim/truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "processing/io/calibration_yaml.h"
#include "processing/io/station_validator.h"
#include "processing/io/yaml_map.h"
#include "sim/sim_station.h"
#include "tests/common/temp_dir.h"

namespace ts::sim {
namespace {

TEST(Truth, DirectoryHoldsTheSceneTheRigAndTheRightGrids) {
  SimStationOptions options;
  options.scene = "forest";
  options.seed = 11;
  options.stage_height_m = 1.4;
  const auto station = *BuildSimStation(options);
  testing::TempDir dir;
  ASSERT_TRUE(WriteTruthDirectory(station->scene, station->rig, dir / "truth").ok());

  const Result<Raster> dem = ReadGeoTiff(dir / "truth/dem.tif");
  ASSERT_TRUE(dem.ok()) << dem.error();
  EXPECT_EQ(dem->cols, 120);
  EXPECT_DOUBLE_EQ(dem->cell_m, 1.0);
  EXPECT_DOUBLE_EQ(dem->min_x_m, -60.0);
  for (int r = 5; r < dem->rows; r += 23)
    for (int c = 3; c < dem->cols; c += 29)
      EXPECT_NEAR(dem->at(r, c),
                  station->scene.TerrainHeight(dem->CellCentreX(c), dem->CellCentreY(r)), 1e-4);
  // The cell whose centre is nearest the station: about -1.4 m.
  EXPECT_NEAR(dem->Interpolate(0, 0), -1.4, 0.2);

  const Result<Raster> fine = ReadGeoTiff(dir / "truth/dem_fine.tif");
  const Result<Raster> objects = ReadGeoTiff(dir / "truth/objects.tif");
  ASSERT_TRUE(fine.ok() && objects.ok());
  EXPECT_EQ(fine->cols, 480);
  EXPECT_EQ(objects->cols, fine->cols);
  double covered = 0;
  for (float v : objects->values) covered += v;

  std::ifstream in(dir / "truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  EXPECT_EQ(truth.at("scene"), "forest");
  EXPECT_EQ(truth.at("seed"), 11);
  EXPECT_DOUBLE_EQ(truth.at("stage_height_m").get<double>(), 1.4);
  EXPECT_NEAR(truth.at("object_cover_fraction").get<double>(), covered / objects->values.size(),
              1e-9);
  EXPECT_GT(truth.at("trees").get<int>(), 10);

  const Result<Calibration> cal = LoadCalibrationYaml(dir / "truth/calibration.yaml");
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_DOUBLE_EQ(cal->rig.left.k1, station->rig.truth.rig.left.k1);
  EXPECT_TRUE(cal->LFromCamera(Side::kRight, 33, -12)
                  .matrix()
                  .isApprox(station->rig.truth.LFromCamera(Side::kRight, 33, -12).matrix(), 1e-12));
}

// A later epoch: the truth records the bowls; the frames differ only by sensor noise where
// the ground did not move (same texture, same rig, same light unless asked).
TEST(Truth, LaterEpochRecordsItsSubsidenceAndKeepsTheScene) {
  SimStationOptions options;
  options.scene = "flat";
  const auto first = *BuildSimStation(options);
  options.epoch = 2;
  Subsidence bowl;
  bowl.centre_m = {0.0, 15.0};
  bowl.radius_m = 5.0;
  bowl.depth_m = 0.4;
  options.subsidence = {bowl};
  const auto second = *BuildSimStation(options);
  testing::TempDir dir;
  ASSERT_TRUE(WriteTruthDirectory(second->scene, second->rig, dir / "truth").ok());
  std::ifstream in(dir / "truth/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  EXPECT_EQ(truth.at("epoch"), 2);
  ASSERT_EQ(truth.at("subsidence").size(), 1u);
  EXPECT_NEAR(truth["subsidence"][0]["volume_m3"].get<double>(), bowl.Volume(),
              0.002 * bowl.Volume());
  EXPECT_DOUBLE_EQ(truth["subsidence"][0]["max_depth_m"].get<double>(), 0.4);

  // Looking away from the bowl (pan 180: -Y), the two epochs see the same radiance.
  Renderer r1(first->scene, first->mesh), r2(second->scene, second->mesh);
  FrameRequest request;
  request.pan_deg = 180.0;
  request.tilt_deg = -20.0;
  request.render.supersampling = 1;
  const cv::Mat a = RenderFrame(r1, *first, request), b = RenderFrame(r2, *second, request);
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  EXPECT_GT(cv::countNonZero(diff), 0);  // new noise
  EXPECT_LT(cv::mean(diff)[0], 3.0);     // nothing else
  // Looking at it (pan 0), the sunk ground shows.
  request.pan_deg = 0.0;
  request.tilt_deg = -5.0;
  cv::Mat range1, range2;
  RenderFrame(r1, *first, request, &range1);
  RenderFrame(r2, *second, request, &range2);
  cv::Mat longer = range2 > range1 + 0.01f;
  EXPECT_GT(cv::countNonZero(longer), 1000);
}

TEST(SimRig, TruthIsImperfectAndNominalKnowsOnlyTheDesign) {
  const SimRig rig = MakeSimRig(5, 1.5);
  EXPECT_NE(rig.truth.rig.left.k1, 0.0);
  EXPECT_NE(rig.truth.stage.pan_zero_deg, 0.0);
  EXPECT_NE(rig.truth.stage.levelling_x_deg, 0.0);
  EXPECT_EQ(rig.nominal.rig.left.k1, 0.0);
  EXPECT_EQ(rig.nominal.stage.pan_zero_deg, 0.0);
  // The nominal levelling is the inclinometer reading, within its accuracy of the truth.
  EXPECT_NEAR(rig.nominal.stage.levelling_x_deg, rig.truth.stage.levelling_x_deg, 0.1);
  EXPECT_NEAR(rig.nominal.stage.height_above_mark_m, 1.5, 0.03);
  std::string why;
  // The tape reaches the tilt axis: the nominal stage hangs the mark from its design tilt axis
  // by what was taped, so the mark stands under the cameras within the tape's 5 mm as it truly
  // does. Over seeds that error is the tape's alone, not the true tilt axis's height over L's
  // origin (no regression on it), which no image shows.
  const int seeds = 200;
  double squares = 0.0, along = 0.0, offsets = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const SimRig r = MakeSimRig(seed, 1.5);
    EXPECT_EQ(r.nominal.stage.tilt_axis_offset_m.z(), 0.12);
    auto camera_above_mark = [](const Calibration& c) {
      return (c.stage.LFromS(0.0, 0.0).translation() - c.stage.StationMarkInL()).z();
    };
    const double tape = camera_above_mark(r.nominal) - camera_above_mark(r.truth) -
                        (r.nominal.stage.rig_offset_m - r.truth.stage.rig_offset_m).z();
    const double axis = r.truth.stage.tilt_axis_offset_m.z() - 0.12;
    squares += tape * tape;
    along += tape * axis;
    offsets += axis * axis;
  }
  EXPECT_NEAR(std::sqrt(squares / seeds), 0.005, 0.001);
  EXPECT_NEAR(along / offsets, 0.0, 0.5);
  EXPECT_TRUE(rig.truth.Check(&why)) << why;
  EXPECT_TRUE(rig.nominal.Check(&why)) << why;
}

TEST(RenderStation, WritesAValidCompleteStationAndItsTruth) {
  SimStationOptions options;
  options.scene = "flat";
  const auto station = *BuildSimStation(options);
  StationRenderOptions render;
  render.render.supersampling = 1;
  render.plan.azimuths = 3;  // keep the test short; the default plan has 12
  render.write_range_images = true;
  testing::TempDir dir;
  int calls = 0;
  ASSERT_TRUE(
      RenderStationDirectory(*station, render, dir / "S", dir / "T", [&](int done, int total) {
        EXPECT_EQ(total, 3);
        EXPECT_EQ(done, ++calls);
      }).ok());
  const Result<StationManifest> m = ValidateStation(dir / "S", {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->pairs.size(), 3u);
  EXPECT_EQ(m->image_width_px, 1392);
  EXPECT_NEAR(m->pairs[1].readback.pan_deg, 120.0, 0.02);
  EXPECT_LT(m->pairs[1].readback.tilt_deg, -10.0);
  // The station gets the nominal calibration; the truth keeps the true one.
  EXPECT_EQ(m->calibration.rig.left.k1, 0.0);
  EXPECT_TRUE(std::filesystem::exists(dir / "T/calibration.yaml"));
  // The true range image puts each pixel on the terrain, through the true calibration at the
  // true encoder angles of truth.json.
  std::ifstream in(dir / "T/truth.json");
  const nlohmann::json truth = nlohmann::json::parse(in);
  const auto& pose = truth.at("true_poses").at(1);
  const cv::Mat range = cv::imread(dir / "T/range/pair_01_left.tif", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(range.type(), CV_32FC1);
  const Calibration& cal = station->rig.truth;
  const CameraModel camera(cal.rig.left);
  const Eigen::Isometry3d l_from_c =
      cal.LFromCamera(Side::kLeft, pose.at("pan_deg"), pose.at("tilt_deg"));
  int on_ground = 0;
  for (int y = 600; y < 1040; y += 97) {
    for (int x = 50; x < 1392; x += 211) {
      const float r = range.at<float>(y, x);
      if (std::isnan(r)) continue;
      const Eigen::Vector3d p = l_from_c * (static_cast<double>(r) * camera.RayFromPixel({x, y}));
      EXPECT_NEAR(p.z(), station->scene.TerrainHeight(p.x(), p.y()), 2e-4) << x << "," << y;
      ++on_ground;
    }
  }
  EXPECT_GT(on_ground, 20);
  // Deterministic per seed: the same images again, byte for byte.
  ASSERT_TRUE(RenderStationDirectory(*station, render, dir / "S2", dir / "T2").ok());
  const Result<StationManifest> again = LoadStationManifest(dir / "S2");
  ASSERT_TRUE(again.ok());
  for (size_t i = 0; i < m->pairs.size(); ++i) {
    EXPECT_EQ(again->pairs[i].left.sha256, m->pairs[i].left.sha256) << i;
    EXPECT_EQ(again->pairs[i].right.sha256, m->pairs[i].right.sha256) << i;
    EXPECT_DOUBLE_EQ(again->pairs[i].readback.pan_deg, m->pairs[i].readback.pan_deg);
  }
}

}  // namespace
}  // namespace ts::sim

namespace ts::sim {
namespace {

// config/sim-rig.yaml must describe the simulated rig's design, or capture against `sim
// serve` would start from the wrong geometry.
TEST(SimRig, ConfigFileMatchesTheSimulatedDesign) {
  const Result<Calibration> config = LoadCalibrationYaml(TS_SOURCE_DIR "/config/sim-rig.yaml");
  ASSERT_FALSE(config.ok());  // a rig config, not a bare calibration: read its block
  YAML::Node root = YAML::LoadFile(TS_SOURCE_DIR "/config/sim-rig.yaml");
  const Calibration cal = ParseCalibration(YamlMap(root["calibration"], "calibration"));
  const Calibration design = DesignCalibration(1.5);
  for (double pan : {0.0, 130.0})
    EXPECT_TRUE(cal.LFromCamera(Side::kRight, pan, -16)
                    .matrix()
                    .isApprox(design.LFromCamera(Side::kRight, pan, -16).matrix(), 1e-12));
  EXPECT_DOUBLE_EQ(cal.rig.left.principal_distance_px, design.rig.left.principal_distance_px);
  EXPECT_EQ(root["devices"]["left_camera"]["id"].as<std::string>(), "TS-SIM-L");
  EXPECT_EQ(root["devices"]["stage"]["port"].as<int>(), 15020);
}

}  // namespace
}  // namespace ts::sim
