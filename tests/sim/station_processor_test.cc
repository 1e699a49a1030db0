// The incremental station against `process` on a rendered station: pairs handed in one by one,
// in capture order (an upper pose right after its row pose), give the same products to the bit
// as the station processed at once; a cancelled or failed job says which step stopped it and
// keeps what the steps before it did.
#include "processing/pipeline/station_processor.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>

#include "processing/dem/dem_evaluation.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/raster.h"
#include "processing/pipeline/rig_check.h"
#include "sim/sim_station.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

class StationProcessorTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir;
    sim::SimStationOptions options;
    options.scene = "slope";  // uphill: upper poses, captured out of index order
    options.seed = 3;
    const auto station = *sim::BuildSimStation(options);
    sim::StationRenderOptions render;
    render.plan.azimuths = 4;  // each test case renders anew (ctest): keep it small
    ASSERT_TRUE(sim::RenderStationDirectory(*station, render, *dir_ / "st", *dir_ / "truth").ok());
    process_.calibration_file = *dir_ / "truth/calibration.yaml";
    process_.set_up_from_calibration_file = true;  // the truth is this station's own
  }
  static void TearDownTestSuite() { delete dir_; }
  // A copy of the rendered station without products, for one run.
  static std::string Copy(const std::string& name) {
    const std::string to = *dir_ / name;
    std::filesystem::copy(*dir_ / "st", to, std::filesystem::copy_options::recursive);
    std::filesystem::remove_all(to + "/products");
    return to;
  }
  static testing::TempDir* dir_;
  static ProcessOptions process_;
};
testing::TempDir* StationProcessorTest::dir_ = nullptr;
ProcessOptions StationProcessorTest::process_;

void ExpectSameRaster(const Raster& a, const Raster& b) {
  ASSERT_EQ(a.values.size(), b.values.size());
  EXPECT_EQ(a.min_x_m, b.min_x_m);
  EXPECT_EQ(0, std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)));
}

// With the stage self-calibrated, so that the tie points found as the pairs came (and the
// adjustment on them) are those of the batch to the bit as well.
TEST_F(StationProcessorTest, PairsHandedInGiveTheProductsOfProcessToTheBit) {
  ProcessOptions options = process_;
  options.self_calibrate_rig = true;
  const Result<ProcessResult> batch = ProcessStation(Copy("batch"), options);
  ASSERT_TRUE(batch) << batch.error();

  const std::string dir = Copy("incremental");
  const StationManifest manifest = *LoadStationManifest(dir);
  ASSERT_GT(manifest.plan.size(), 4u) << "no upper pose: the order would not be tested";
  StationInputs inputs;
  inputs.dir = dir;
  inputs.manifest = manifest;
  StationProcessor processor(dir, options);
  std::vector<PairRecord> capture_order = manifest.pairs;  // as the capture committed them
  for (const PairRecord& p : capture_order) {
    const Result<StereoPairImages> images = LoadPairImages(inputs, p);
    ASSERT_TRUE(images) << images.error();
    processor.AddPair(p, images->left, images->right);
  }
  const Result<ProcessResult> incremental = processor.Finish();
  ASSERT_TRUE(incremental) << incremental.error();
  EXPECT_EQ(incremental->summary.Find("matching")->counts["matched_during_capture"].get<int>(),
            static_cast<int>(manifest.pairs.size()));
  ExpectSameRaster(batch->dem, incremental->dem);
  ExpectSameRaster(batch->dem_std, incremental->dem_std);
  EXPECT_EQ(batch->cloud.size(), incremental->cloud.size());
  EXPECT_EQ(batch->point_class, incremental->point_class);
  EXPECT_EQ(batch->terrain_correction.total_mgal, incremental->terrain_correction.total_mgal);
  EXPECT_EQ(incremental->summary.Find("rig")->counts["pairs_tied_during_capture"].get<int>(),
            static_cast<int>(manifest.pairs.size()));
  EXPECT_TRUE(incremental->report["rig"]["used"].get<bool>());
  EXPECT_EQ(batch->report["rig"], incremental->report["rig"]);
  // The report says how to reproduce it.
  const nlohmann::json& r = incremental->report;
  EXPECT_EQ(r["calibration"]["source"], process_.calibration_file + " (stage self-calibrated)");
  EXPECT_EQ(r["calibration"]["sha256"].get<std::string>().size(), 64u);
  EXPECT_FALSE(r["software"]["version"].get<std::string>().empty());
  EXPECT_EQ(r["options"]["kriging"]["max_distance_m"].get<double>(), 5.5);
  EXPECT_EQ(r["options"]["matching"]["lsm"]["half_window_px"].get<double>(), 8);
  for (const char* step : {"load", "matching", "rig", "blunder_filter", "sight_line_objects",
                           "ground_filter", "underside_patches", "seen_through_ground", "kriging",
                           "horizon_limit", "terrain_correction", "products"})
    EXPECT_TRUE(r["timings_s"].contains(step)) << step;
}

// One test case for both (each case renders the station again under ctest).
TEST_F(StationProcessorTest, ACancelledOrFailedJobSaysWhichStepStoppedIt) {
  {  // cancelled once matching has started: it stops between pairs
    const std::string dir = Copy("cancelled");
    std::atomic<int> steps_started{0};
    ProcessControl control;
    control.progress = [&](const ProcessProgress& p) {
      if (p.step_number > steps_started) steps_started = p.step_number;
    };
    control.should_stop = [&] { return steps_started >= 2; };
    StationProcessor processor(dir, process_, control);
    const Result<ProcessResult> r = processor.Finish();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), "cancelled during matching");
    EXPECT_EQ(processor.summary().Find("load")->state, StepSummary::State::kSucceeded);
    EXPECT_EQ(processor.summary().termination, ProcessSummary::Termination::kCancelled);
    EXPECT_FALSE(std::filesystem::exists(dir + "/products/report.json"));
  }
  {  // a square with no matched point in it
    const std::string dir = Copy("failed");
    ProcessOptions options = process_;
    options.dem_half_size_m = 5;
    options.cloud_margin_m = 0;
    options.matching.min_depth_m = 60;  // only far ground is matched
    StationProcessor processor(dir, options);
    const Result<ProcessResult> r = processor.Finish();
    ASSERT_FALSE(r);
    const ProcessSummary& s = processor.summary();
    EXPECT_EQ(s.termination, ProcessSummary::Termination::kFailed);
    const StepSummary* blunders = s.Find("blunder_filter");
    ASSERT_NE(blunders, nullptr);
    EXPECT_EQ(blunders->state, StepSummary::State::kFailed);
    EXPECT_NE(r.error().find("points lies within 5 m of the station"), std::string::npos)
        << r.error();
    EXPECT_GT(s.Find("matching")->counts["points"].get<int>(), 0);
    EXPECT_EQ(s.Find("kriging"), nullptr);  // never started
  }
}

bool Warns(const nlohmann::json& report, const std::string& what) {
  for (const auto& w : report["warnings"])
    if (w.get<std::string>().find(what) != std::string::npos) return true;
  return false;
}

// Issue 21: a tripod bumped after the rig's calibration (its tilt zero 0.3 deg off, which tilts
// ground 30 m out by 16 cm). `process` sees it in the seams and says so; with
// --self-calibrate-rig it recovers the DEM of the true calibration. A whole row of poses: the
// fixture's four azimuths do not overlap, and a tilt zero is seen where neighbours do.
TEST(StationProcessor, ABumpedRigIsSeenInTheSeamsAndSelfCalibrated) {
  testing::TempDir dir;
  sim::SimStationOptions scene;
  scene.seed = 4;
  const auto station = *sim::BuildSimStation(scene);
  sim::StationRenderOptions render;
  render.plan.upper_poses = false;
  ASSERT_TRUE(sim::RenderStationDirectory(*station, render, dir / "st", dir / "truth").ok());
  const Result<Calibration> truth = LoadCalibrationYaml(dir / "truth/calibration.yaml");
  ASSERT_TRUE(truth) << truth.error();
  const Result<Raster> true_dem = ReadGeoTiff(dir / "truth/dem.tif");
  ASSERT_TRUE(true_dem) << true_dem.error();
  Calibration bumped = *truth;
  bumped.stage.tilt_zero_deg -= 0.3;
  ASSERT_TRUE(SaveCalibrationYaml(bumped, dir / "bumped.yaml"));
  int runs = 0;
  const auto process = [&](const std::string& calibration, bool self_calibrate) {
    const std::string copy = dir / ("run" + std::to_string(++runs));
    std::filesystem::copy(dir / "st", copy, std::filesystem::copy_options::recursive);
    ProcessOptions options;
    options.calibration_file = dir / calibration;
    options.self_calibrate_rig = self_calibrate;
    Result<ProcessResult> r = ProcessStation(copy, options);
    EXPECT_TRUE(r) << r.error();
    EXPECT_TRUE(std::filesystem::exists(copy + "/products/seams.png"));
    return r ? *std::move(r) : ProcessResult{};
  };
  const auto rmse = [&](const ProcessResult& r) {
    return EvaluateDem(r.dem, *true_dem, truth->stage.StationMarkInL().head<2>()).rmse_m;
  };
  const ProcessResult reference = process("truth/calibration.yaml", false);
  EXPECT_FALSE(Warns(reference.report, "seams do not close"));
  EXPECT_FALSE(reference.report["rig"]["used"].get<bool>());

  const ProcessResult as_given = process("bumped.yaml", false);
  EXPECT_TRUE(Warns(as_given.report, "seams do not close"));

  const ProcessResult self = process("bumped.yaml", true);
  const nlohmann::json& rig = self.report["rig"];
  EXPECT_TRUE(rig["used"].get<bool>());
  EXPECT_EQ(self.report["calibration"]["source"],
            std::string(dir / "bumped.yaml") +
                " (levelling and height: station) (stage self-calibrated)");
  EXPECT_GE(rig["seams"]["after"]["within_2_sigma"].get<double>(), RigCheck::kClosedShare);
  EXPECT_FALSE(Warns(self.report, "seams do not close"));
  // The bump is taken back. Tilt zero and the rig's omega turn the views about one axis: the
  // panorama sees their difference, and one of them is held.
  const auto value = [&](const char* name) {
    return rig["parameters"][name]["value"].get<double>();
  };
  EXPECT_NEAR(value("rig_omega_deg") - value("tilt_zero_deg"),
              truth->stage.rig_rotation_opk_deg.x() - truth->stage.tilt_zero_deg, 0.01);
  std::printf("DEM RMSE: true calibration %.3f m, bumped %.3f m, self-calibrated %.3f m\n",
              rmse(reference), rmse(as_given), rmse(self));
  EXPECT_LT(rmse(self), 1.1 * rmse(reference));
}

}  // namespace
}  // namespace ts
