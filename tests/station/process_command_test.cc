// `process`, `evaluate` and `ground-filter` through the real command line.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "processing/io/calibration_yaml.h"
#include "processing/io/point_cloud_file.h"
#include "processing/io/raster.h"
#include "tests/common/isprs_sample.h"
#include "tests/common/paper_rig.h"
#include "tests/common/station_fixture.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using testing::RunCommand;

std::string Exe() { return TS_TOPOSTATION_EXE; }

TEST(ProcessCommand, BadInputGivesOneClearError) {
  testing::TempDir dir;
  const std::string s = dir / "S";
  testing::MakeStation(s, 2, 2);
  auto error_of = [](const std::string& args) {
    const auto r = RunCommand(Exe() + " process " + args + " 2>&1");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    return r.out;
  };
  EXPECT_NE(error_of(s + " --calibration " + (dir / "none.yaml")).find("none.yaml"),
            std::string::npos);
  std::ofstream(dir / "gcps.yaml") << "crs: EPSG:32633\npoints: []\n";
  EXPECT_NE(error_of(s + " --gcps " + (dir / "gcps.yaml")).find("gcps.yaml: points"),
            std::string::npos);
  EXPECT_NE(error_of(dir / "nowhere").find("nowhere"), std::string::npos);
  EXPECT_NE(error_of(s + " --object-shadow-reach-m=-1").find("object_shadow_reach_m"),
            std::string::npos);
  // Declared ranges: a value no site has is named with its value, before any work.
  EXPECT_NE(error_of(s + " --max-distance-m 1e9")
                .find("kriging.max_distance_m must be in [0.1, 50] m, got 1e+09"),
            std::string::npos);
  // --set NAME=VALUE: the name, the value and the range, each named.
  EXPECT_NE(error_of(s + " --set ground.slope").find("expected NAME=VALUE"), std::string::npos);
  EXPECT_NE(error_of(s + " --set ground.slop=0.1").find("no option ground.slop"),
            std::string::npos);
  EXPECT_NE(error_of(s + " --set ground.slope=steep").find("steep is not a value of ground.slope"),
            std::string::npos);
  EXPECT_NE(error_of(s + " --set free_space.enabled=maybe").find("free_space.enabled"),
            std::string::npos);
  EXPECT_NE(error_of(s + " --set ground.slope=-1").find("ground.slope must be in [0, 10]"),
            std::string::npos);
  // Images of noise: nothing matches, and the error says so (it was "could not write the PLY").
  EXPECT_NE(error_of(s + " -q").find("no pair gave a single match"), std::string::npos);
  std::ofstream(s + "/raw/pair_01_right.png", std::ios::app) << "garbage";
  EXPECT_NE(error_of(s).find("pair_01_right.png"), std::string::npos);
}

TEST(EvaluateCommand, NeedsProductsAndTruth) {
  testing::TempDir dir;
  testing::MakeStation(dir / "S", 2, 2);
  const auto r =
      RunCommand(Exe() + " evaluate " + (dir / "S") + " --truth " + (dir / "T") + " 2>&1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("products/dem.tif"), std::string::npos) << r.out;
}

// A station processed on a calibration that puts L's origin 12 mm lower under the tilt axis
// than the truth's does (the height no image shows) sees the true ground 12 mm higher: no error
// of its own. The same DEM against a truth of its own datum is 12 mm off.
TEST(EvaluateCommand, TheTruthIsLiftedIntoTheProcessedFramesHeightDatum) {
  testing::TempDir dir;
  const std::string s = dir / "S", t = dir / "T";
  std::filesystem::create_directories(s + "/products");
  std::filesystem::create_directories(t);
  Raster truth = Raster::Make(-30.0, 30.0, 1.0, 60, 60);
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 60; ++c)
      truth.at(r, c) = static_cast<float>(-1.5 + 0.05 * truth.CellCentreX(c));
  ASSERT_TRUE(WriteGeoTiff(truth, t + "/dem.tif"));
  Calibration cal = testing::PaperCalibration();
  cal.stage.tilt_axis_offset_m = {0.0, 0.02, 0.120};
  ASSERT_TRUE(SaveCalibrationYaml(cal, t + "/calibration.yaml"));
  Raster dem = truth;
  for (float& v : dem.values) v += 0.012f;
  ASSERT_TRUE(WriteGeoTiff(dem, s + "/products/dem.tif"));
  std::ofstream(s + "/products/terrain_correction.json")
      << R"({"terrain_correction_mgal": 0.01, "sigma_mgal": 0.001})";
  auto evaluate = [&](double tilt_axis_height_m) {
    std::ofstream(s + "/products/report.json") << nlohmann::json{
        {"calibration", {{"pan_zero_deg", 0.0}, {"tilt_axis_height_m", tilt_axis_height_m}}},
        {"station_mark", {0.0, 0.0, -1.5}}}.dump();
    const auto r = RunCommand(Exe() + " evaluate " + s + " --truth " + t + " 2>&1");
    EXPECT_EQ(r.exit_code, 0) << r.out;
    std::ifstream written(s + "/products/evaluation.json");
    return nlohmann::json::parse(written);
  };
  const nlohmann::json lifted = evaluate(0.132);
  EXPECT_NEAR(lifted["height_datum_m"].get<double>(), 0.012, 1e-12);
  EXPECT_LT(lifted["dem_rmse_m"].get<double>(), 1e-6);
  EXPECT_NEAR(evaluate(0.120)["dem_rmse_m"].get<double>(), 0.012, 1e-6);
}

TEST(GroundFilterCommand, WritesTheGroundPointsUnchanged) {
  testing::TempDir dir;
  const std::string in = testing::IsprsPath("samp21");
  const auto r = RunCommand(Exe() + " ground-filter " + in + " --out " + (dir / "g.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto all = ReadPointCloudXyz(in).value();
  const auto ground = ReadPointCloudXyz(dir / "g.ply").value();
  ASSERT_GT(ground.size(), all.size() / 2);
  ASSERT_LT(ground.size(), all.size());
  // Every written point is one of the input's, bit for bit.
  std::set<std::tuple<double, double, double>> input;
  for (const auto& p : all) input.emplace(p.x(), p.y(), p.z());
  for (const auto& p : ground) ASSERT_TRUE(input.count({p.x(), p.y(), p.z()}));
  const auto bad = RunCommand(Exe() + " ground-filter " + (dir / "none.pcd") + " --out " +
                              (dir / "x.ply") + " 2>&1");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.out.find("none.pcd"), std::string::npos);
  // A window no object needs ran without end; now it is refused by its declared range.
  const auto huge = RunCommand(Exe() + " ground-filter " + in + " --out " + (dir / "x.ply") +
                               " --window-m 1e9 2>&1");
  EXPECT_EQ(huge.exit_code, 1);
  EXPECT_NE(huge.out.find("max_window_m must be in [0.05, 100] m, got 1e+09"), std::string::npos)
      << huge.out;
}

// Clouds a reader can parse but the filter cannot use: one clear error naming the file, never
// "0 of 100 points are ground" or an allocation failure.
TEST(GroundFilterCommand, CloudsWithoutAUsableExtentGetOneClearError) {
  testing::TempDir dir;
  auto run = [&](const std::string& name, const std::vector<Eigen::Vector3d>& points) {
    EXPECT_TRUE(WritePly(dir / name, points));
    return RunCommand(Exe() + " ground-filter " + (dir / name) + " --out " + (dir / "g.ply") +
                      " 2>&1");
  };
  const double nan = std::nan("");
  const auto no_finite = run("nan.ply", std::vector<Eigen::Vector3d>(100, {nan, nan, nan}));
  EXPECT_EQ(no_finite.exit_code, 1);
  EXPECT_NE(no_finite.out.find("nan.ply: no point with finite coordinates"), std::string::npos)
      << no_finite.out;
  for (const double far : {1e7, 3e38}) {
    const auto spread = run("far.ply", {{0, 0, 0}, {far, -far, 1}, {5, 5, 0}});
    EXPECT_EQ(spread.exit_code, 1) << far;
    EXPECT_NE(spread.out.find("far.ply: the points lie too far apart"), std::string::npos)
        << spread.out;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "g.ply"));
}

}  // namespace
}  // namespace ts
