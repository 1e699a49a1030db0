// `capture --calibration` over the real drivers against the simulated station showing
// calibration targets: a control field's grid of stage poses, and a board moved between
// pairs taken on demand; each session then calibrated by `calibrate stereo` and compared with
// the simulated rig's truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "processing/io/calibration_yaml.h"
#include "processing/io/station_validator.h"
#include "sim/sim_server.h"
#include "tests/common/calibration_errors.h"
#include "tests/common/sim_rig_config.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

namespace fs = std::filesystem;
const std::string kExe = TS_TOPOSTATION_EXE;

class CalibrationCaptureTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::SimStationOptions options;
    options.scene = "flat";
    options.seed = 3;
    station_ = *sim::BuildSimStation(options);
  }

  // Serves the targets; returns the rig config that reaches them.
  std::string Serve(const sim::ServedCalibration& targets, int port) {
    sim::SimServeOptions o;
    o.stage_port = port;
    o.stage_pty = false;
    o.calibration = targets;
    auto server = sim::SimServer::Start(station_, o);
    EXPECT_TRUE(server.ok()) << server.error();
    if (server) server_ = std::move(*server);
    return testing::WriteSimRigConfig(dir_ / "rig.yaml", testing::TcpStage(port));
  }

  nlohmann::json RunJson(const std::string& command) {
    const testing::CommandOutput r = testing::RunCommand(command + " 2>" + (dir_ / "stderr.txt"));
    std::ifstream err(dir_ / "stderr.txt");
    const std::string errors((std::istreambuf_iterator<char>(err)), {});
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << errors;
    return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
  }

  // The calibration written to `file` against the truth: each error within k of its sigma,
  // and within the absolute bounds given.
  void ExpectNearTruth(const std::string& file, double k, double c_rel, double pp_px,
                       double baseline_m, double angle_deg) {
    const Result<Calibration> cal = LoadCalibrationYaml(file);
    ASSERT_TRUE(cal.ok()) << cal.error();
    const StereoRig& truth = station_->rig.truth.rig;
    for (Side side : {Side::kLeft, Side::kRight}) {
      const CameraIntrinsics& e = side == Side::kLeft ? cal->rig.left : cal->rig.right;
      const CameraIntrinsics& t = side == Side::kLeft ? truth.left : truth.right;
      const CameraPrecision& p = side == Side::kLeft ? cal->left_precision : cal->right_precision;
      ASSERT_TRUE(p.known);
      const double dc = e.principal_distance_px - t.principal_distance_px;
      EXPECT_LT(std::abs(dc), std::min(k * p.sigma[0], c_rel * t.principal_distance_px))
          << SideName(side) << " c " << e.principal_distance_px << " +- " << p.sigma[0];
      const double dx = e.principal_point_x_px - t.principal_point_x_px;
      const double dy = e.principal_point_y_px - t.principal_point_y_px;
      EXPECT_LT(std::abs(dx), std::min(k * p.sigma[1], pp_px))
          << SideName(side) << " xp " << dx << " +- " << p.sigma[1];
      EXPECT_LT(std::abs(dy), std::min(k * p.sigma[2], pp_px))
          << SideName(side) << " yp " << dy << " +- " << p.sigma[2];
    }
    const StereoPrecision& s = cal->stereo_precision;
    ASSERT_TRUE(s.known);
    EXPECT_LT(std::abs(cal->rig.baseline_m - truth.baseline_m),
              std::min(k * s.baseline_sigma_m, baseline_m))
        << cal->rig.baseline_m - truth.baseline_m << " +- " << s.baseline_sigma_m;
    const Eigen::Vector3d angles = RelativeAnglesDeg(cal->rig) - RelativeAnglesDeg(truth);
    for (int j = 0; j < 3; ++j)
      EXPECT_LT(std::abs(angles[j]), std::min(k * s.relative_sigma_deg[j] + 1e-4, angle_deg))
          << "angle " << j << ": " << angles[j] << " +- " << s.relative_sigma_deg[j];
  }

  static std::shared_ptr<const sim::SimStation> station_;
  testing::TempDir dir_;
  std::unique_ptr<sim::SimServer> server_;
};
std::shared_ptr<const sim::SimStation> CalibrationCaptureTest::station_;

// The field's grid over the stage, as a station directory that validates and resumes; the
// calibration from it meets the targets (c 0.05 %, principal point 0.3 px, baseline
// 0.2 mm, angles 0.005 deg) and lies within 4 sigma of the truth.
TEST_F(CalibrationCaptureTest, FieldPosesCaptureAndCalibrateTheTrueRig) {
  sim::ServedCalibration targets;
  targets.kind = "field";
  const std::string rig = Serve(targets, 15171);
  ASSERT_TRUE(server_);
  const std::string truth = dir_ / "truth";
  fs::create_directories(truth);
  ASSERT_TRUE(
      sim::WriteServedCalibrationTruth(station_->rig, station_->scene.seed, targets, truth).ok());
  const std::string out = dir_ / "field";
  const nlohmann::json capture =
      RunJson(kExe + " capture --calibration field --rig " + rig + " --out " + out + " --json");
  EXPECT_EQ(capture.value("captured_now", 0), 36);
  const Result<StationManifest> m = ValidateStation(out, {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  const std::vector<StagePose> grid = MakeFieldPoseGrid({});
  ASSERT_EQ(m->plan.size(), grid.size());
  for (size_t k = 0; k < grid.size(); ++k) {
    EXPECT_DOUBLE_EQ(m->plan[k].pan_deg, grid[k].pan_deg);
    EXPECT_NEAR(m->pairs[k].readback.tilt_deg, grid[k].tilt_deg, 0.05);
  }
  const nlohmann::json resumed = RunJson(kExe + " capture --calibration field --rig " + rig +
                                         " --out " + out + " --resume --json");
  EXPECT_EQ(resumed.value("captured_now", -1), 0);
  EXPECT_EQ(resumed.value("already_present", 0), 36);

  const nlohmann::json cal = RunJson(
      kExe + " calibrate stereo --left '" + out + "/raw/*_left.png' --right '" + out +
      "/raw/*_right.png' --control-field " + truth + "/field.yaml --marks " + truth +
      "/marks.yaml --start " + out + "/design.yaml --out " + (dir_ / "cal.yaml") + " --json");
  EXPECT_GT(cal["control_field"].value("targets_found", 0), 180);
  ExpectNearTruth(dir_ / "cal.yaml", 4.0, 0.0005, 0.3, 0.0002, 0.005);
}

// Pairs on demand (a line on stdin each): placements without a board, or where the chessboard
// runs off the frame, are not kept; each kept pair is on disk with its corners in
// session.json; a second run (at an interval) numbers on. The pairs calibrate the rig within
// 4 sigma of the truth.
TEST_F(CalibrationCaptureTest, BoardPairsOnDemandAreCheckedKeptAndCalibrate) {
  sim::ServedCalibration targets;
  targets.kind = "chessboard";
  targets.board.supersampling = 2;
  targets.board.empty_share = 0.2;  // a helper often out of view
  const std::string rig = Serve(targets, 15172);
  ASSERT_TRUE(server_);
  const std::string out = dir_ / "boards";
  const std::string board = " --chessboard 16x11 --square 0.07";
  const nlohmann::json first =
      RunJson("yes '' 2>/dev/null | " + kExe + " capture --calibration chessboard" + board +
              " --rig " + rig + " --out " + out + " --pairs 8 --exposure-us 3000 --json");
  EXPECT_EQ(first.value("kept", 0), 8);
  // Without a frame triggered again (a lost frame, or a retake for the exposure: the helper
  // moves the board meanwhile), the k-th pair shows the k-th placement: those without a board
  // are dropped, a chessboard is found whole or not at all.
  const std::vector<sim::BoardPlacement> placements =
      sim::PlanBoardSession(station_->rig, station_->scene.seed, targets.board);
  EXPECT_EQ(first["pairs"].size(), 8u + first.value("not_kept", -1));
  const bool one_trigger_per_pair =
      first.value("frame_retries", -1) == 0 && first.value("retakes", -1) == 0;
  EXPECT_EQ(first.value("retakes", -1), 0) << "the board session's exposure needs no retake";
  int empty = 0;
  for (size_t k = 0; k < first["pairs"].size(); ++k) {
    const nlohmann::json& p = first["pairs"][k];
    const int corners = p["corners_left"].get<int>() + p["corners_right"].get<int>();
    EXPECT_EQ(p["kept"].get<bool>(), corners > 0);
    EXPECT_TRUE(corners % 176 == 0) << corners;
    if (one_trigger_per_pair && !placements[k].board) {
      EXPECT_EQ(corners, 0) << "placement " << k;
      ++empty;
    }
  }
  if (one_trigger_per_pair) {
    EXPECT_GT(empty, 0) << first.dump();
  }
  const nlohmann::json second =
      RunJson(kExe + " capture --calibration chessboard" + board + " --rig " + rig + " --out " +
              out + " --pairs 10 --interval 0.2 --json </dev/null");
  EXPECT_EQ(second.value("kept", 0), 10);
  EXPECT_TRUE(fs::exists(out + "/left/10.png") && fs::exists(out + "/right/10.png"));
  EXPECT_FALSE(fs::exists(out + "/left/11.png"));
  std::ifstream session_file(out + "/session.json");
  const nlohmann::json session = nlohmann::json::parse(session_file);
  EXPECT_EQ(session["pairs"].size(), 10u);
  EXPECT_GT(session["coverage"]["left"]["share"].get<double>(), 0.5);

  RunJson(kExe + " calibrate stereo --left '" + out + "/left/*.png' --right '" + out +
          "/right/*.png'" + board + " --out " + (dir_ / "cal.yaml") + " --json");
  ExpectNearTruth(dir_ / "cal.yaml", 4.0, 0.0005, 3.0, 0.0005, 0.05);
}

// Nothing to capture with: a ChArUco session without its board, and a chessboard named as
// ChArUco, are one clear error each, before any device is opened.
TEST_F(CalibrationCaptureTest, BoardKindAndFlagsMustAgree) {
  const std::string rig = testing::WriteSimRigConfig(dir_ / "rig.yaml", testing::TcpStage(15173));
  for (const std::string flags :
       {"--calibration charuco", "--calibration chessboard --charuco 12x9"}) {
    const testing::CommandOutput r = testing::RunCommand(kExe + " capture " + flags + " --rig " +
                                                         rig + " --out " + (dir_ / "x") + " 2>&1");
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("--charuco"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "x"));
  }
}

}  // namespace
}  // namespace ts
