// topostation calibrate camera on the real chessboard views, and its bad inputs.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "processing/calibration/rig_cameras.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/station_manifest.h"
#include "tests/common/station_fixture.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using testing::RunCommand;

const std::string kExe = TS_TOPOSTATION_EXE;
const std::string kBoards = TS_SHARED_DATA_DIR "/calibration/opencv_stereo_chessboard";

// The right camera: one of its 13 views does not show the whole board and is named; the file
// written reads back as the camera the JSON describes, its sigmas beside it.
TEST(CalibrateCommand, RightCameraFromTheRealBoardsWritesItsFile) {
  testing::TempDir dir;
  const std::string out = dir / "right.yaml";
  const auto r =
      RunCommand(kExe + " calibrate camera --images '" + kBoards +
                 "/right*.jpg' --chessboard 9x6 --square 1 --out " + out + " --json 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["views_used"], 12);
  ASSERT_EQ(j["views_skipped"].size(), 1u);
  EXPECT_NE(j["views_skipped"][0].get<std::string>().find("right"), std::string::npos);
  EXPECT_LT(j["rms_px"].get<double>(), 0.3);  // sub-pixel corners of a sharp board
  EXPECT_GT(j["sigma"]["c"].get<double>(), 0.0);
  const Result<CameraIntrinsics> camera = LoadCameraCalibrationYaml(out);
  ASSERT_TRUE(camera.ok()) << camera.error();
  EXPECT_EQ(camera->width_px, 640);
  EXPECT_DOUBLE_EQ(camera->principal_distance_px, j["fy"].get<double>());
  EXPECT_DOUBLE_EQ(camera->principal_point_x_px, j["cx"].get<double>());
}

// The calibration workflow on the simulator: a rendered session of a station's true rig, a
// chessboard with circle markers (the plain board's path is the real boards' tests'),
// calibrated by the command a field team runs, compared with the truth the session wrote.
TEST(CalibrateCommand, SimulatedChessboardSessionGivesTheTrueRig) {
  testing::TempDir dir;
  const std::string views = dir / "views", truth = dir / "truth", out = dir / "cal.yaml";
  const auto render = RunCommand(kExe + " sim render --calibration chessboard --seed 3 " +
                                 "--board-circle-markers --placements 10 --out " + views +
                                 " --truth " + truth + " 2>&1");
  ASSERT_EQ(render.exit_code, 0) << render.out;
  const auto session = nlohmann::json::parse(std::ifstream(views + "/session.json"));
  EXPECT_EQ(session["board"]["columns"], 16);
  EXPECT_NE(session["calibrate"].get<std::string>().find("--chessboard 16x11 --circle-markers"),
            std::string::npos);
  const auto placements =
      nlohmann::json::parse(std::ifstream(truth + "/board_session.json"))["placements"];
  ASSERT_EQ(placements.size(), 10u);
  for (const char* side : {"left", "right"})
    EXPECT_TRUE(std::filesystem::exists(views + "/" + side + "/10.png")) << side;
  const auto r = RunCommand(
      kExe + " calibrate stereo --left '" + views + "/left/*.png' --right '" + views +
      "/right/*.png' --chessboard 16x11 --circle-markers --square 0.07 " + "--stage-from " + truth +
      "/calibration.yaml --out " + out + " --json 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const Result<Calibration> true_rig = LoadCalibrationYaml(truth + "/calibration.yaml");
  ASSERT_TRUE(true_rig.ok()) << true_rig.error();
  const CameraIntrinsics& left = true_rig->rig.left;
  // Each within four of its sigmas, and the sigmas small: a calibration worth having.
  const double c = j["left"]["fy"].get<double>(), c_sigma = j["left"]["sigma"]["c"];
  EXPECT_NEAR(c, left.principal_distance_px, 4 * c_sigma);
  EXPECT_LT(c_sigma / c, 5e-4);
  EXPECT_NEAR(j["left"]["cx"].get<double>(), left.principal_point_x_px,
              4 * j["left"]["sigma"]["xp"].get<double>());
  const double baseline_sigma = j["stereo"]["baseline_sigma"];
  EXPECT_NEAR(j["stereo"]["baseline"].get<double>(), true_rig->rig.baseline_m, 4 * baseline_sigma);
  EXPECT_LT(baseline_sigma, 2e-4);
  const Result<Calibration> written = LoadCalibrationYaml(out);
  ASSERT_TRUE(written.ok()) << written.error();
  EXPECT_TRUE(written->stereo_precision.known);
}

// A ChArUco session of the simulated rig, boards off the frame's edges included: the command
// the session names calibrates the pair, the principal distance and baseline near the truth.
TEST(CalibrateCommand, SimulatedCharucoSessionGivesTheTrueRig) {
  testing::TempDir dir;
  const std::string views = dir / "views", truth = dir / "truth", out = dir / "cal.yaml";
  const auto render = RunCommand(kExe + " sim render --calibration charuco --seed 5 " +
                                 "--placements 12 --out " + views + " --truth " + truth + " 2>&1");
  ASSERT_EQ(render.exit_code, 0) << render.out;
  const auto session = nlohmann::json::parse(std::ifstream(views + "/session.json"));
  EXPECT_TRUE(session["board"]["charuco"].get<bool>());
  EXPECT_NE(session["calibrate"].get<std::string>().find("--charuco 17x12"), std::string::npos);
  const auto r = RunCommand(kExe + " calibrate stereo --left '" + views + "/left/*.png' --right '" +
                            views + "/right/*.png' --charuco 17x12 --square 0.07 --out " + out +
                            " --json 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const Result<Calibration> true_rig = LoadCalibrationYaml(truth + "/calibration.yaml");
  ASSERT_TRUE(true_rig.ok()) << true_rig.error();
  EXPECT_NEAR(j["left"]["fy"].get<double>() / true_rig->rig.left.principal_distance_px, 1.0, 1e-3);
  EXPECT_NEAR(j["stereo"]["baseline"].get<double>(), true_rig->rig.baseline_m, 5e-4);
  EXPECT_GT(j["left"]["views_used"].get<int>(), 8) << "partial boards count";
  const auto both = RunCommand(kExe + " calibrate camera --images '" + views +
                               "/left/*.png' --charuco 17x12 --circle-markers --out " +
                               (dir / "bad.yaml") + " 2>&1");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.out.find("--circle-markers"), std::string::npos) << both.out;
  const auto bad =
      RunCommand(kExe + " calibrate stereo --left '" + views + "/left/*.png' " + "--right '" +
                 views + "/right/*.png' --charuco 2x12 --out " + (dir / "bad.yaml") + " 2>&1");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("--charuco: expected SQUARESxSQUARES"), std::string::npos) << bad.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.yaml"));
}

// A control field session of the simulated rig (seed 003's calibration range): hand marks in
// the left images only, the rest found; the rig within four sigmas of the truth, one camera too,
// and then the stage from the same session, the cameras held and refined.
TEST(CalibrateCommand, ControlFieldSessionGivesTheTrueRigAndItsStage) {
  testing::TempDir dir;
  const std::string views = dir / "field", truth = dir / "truth", out = dir / "cal.yaml";
  const auto render = RunCommand(kExe + " sim render --calibration field --seed 4 --field-pans 5 " +
                                 "--out " + views + " --truth " + truth + " 2>&1");
  ASSERT_EQ(render.exit_code, 0) << render.out;
  const std::string field = " --control-field " + views + "/field.yaml --marks " + views +
                            "/marks.yaml --start " + views + "/design.yaml";
  const auto r =
      RunCommand(kExe + " calibrate stereo --left '" + views + "/left/*.png' --right '" + views +
                 "/right/*.png'" + field + " --out " + out + " --json 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const Result<Calibration> true_rig = LoadCalibrationYaml(truth + "/calibration.yaml");
  ASSERT_TRUE(true_rig.ok()) << true_rig.error();
  for (const auto& [side, camera] :
       {std::pair{"left", true_rig->rig.left}, std::pair{"right", true_rig->rig.right}}) {
    const auto& c = j[side];
    EXPECT_NEAR(c["fy"].get<double>(), camera.principal_distance_px,
                4 * c["sigma"]["c"].get<double>());
    EXPECT_NEAR(c["cx"].get<double>(), camera.principal_point_x_px,
                4 * c["sigma"]["xp"].get<double>());
    EXPECT_NEAR(c["cy"].get<double>(), camera.principal_point_y_px,
                4 * c["sigma"]["yp"].get<double>());
    EXPECT_LT(c["rms_px"].get<double>(), 0.05) << side;
  }
  EXPECT_NEAR(j["stereo"]["baseline"].get<double>(), true_rig->rig.baseline_m,
              4 * j["stereo"]["baseline_sigma"].get<double>());
  EXPECT_GT(j["control_field"]["targets_found"].get<int>(), 120);  // of 200; 5 pans see 70 %
  // The halves (alternate stage poses) agree; the verdict is stated with its reason.
  for (const auto& m : j["validation"]["maps"]) {
    EXPECT_TRUE(m["split"].get<bool>());
    EXPECT_LT(m["consistency"].get<double>(), 3.0);
  }
  EXPECT_NE(j["validation"]["verdict"], "overfitted") << j["validation"]["reason"];
  EXPECT_TRUE(LoadCalibrationYaml(out).ok());

  // The stage at the same field (issue 21): calibrate rig on the session's stage poses, the
  // cameras just calibrated held. How each pose's left camera moves from the first pose's does
  // not depend on the levelling or the azimuth datum; it comes within 0.01 deg and 2 mm of the
  // truth, from the design stage's 0.1 deg or more.
  const auto calibrate_rig = [&](const std::string& rig_out, const std::string& flags) {
    return RunCommand(kExe + " calibrate rig --field-session " + views + " --control-field " +
                      views + "/field.yaml --marks " + views + "/marks.yaml --calibration " + out +
                      " --out " + rig_out + flags + " --json 2>/dev/null");
  };
  const std::string rig_out = dir / "rig.yaml";
  const auto rig = calibrate_rig(rig_out, "");
  ASSERT_EQ(rig.exit_code, 0) << rig.out;
  const auto g = nlohmann::json::parse(rig.out);
  ASSERT_EQ(g["control_fields"].size(), 1u);
  EXPECT_GT(g["control_fields"][0]["targets"].get<int>(), 120);
  EXPECT_LT(g["control_fields"][0]["rms_px"].get<double>(), 0.1);
  // The cameras held are this session's calibration, not exact: their covariance is carried
  // into the offsets' sigmas, and report.json says how much of each sigma it is.
  for (const char* offset : {"tilt_axis_offset_x_m", "rig_offset_y_m", "rig_offset_z_m"}) {
    const auto& p = g["parameters"][offset];
    const double share = p["sigma_from_held_cameras"].get<double>();
    EXPECT_GT(share, 0.0) << offset;
    EXPECT_LE(share, p["sigma"].get<double>()) << offset;
  }
  const Result<Calibration> calibrated = LoadCalibrationYaml(out),
                            staged = LoadCalibrationYaml(rig_out);
  ASSERT_TRUE(calibrated.ok() && staged.ok());
  const auto session = nlohmann::json::parse(std::ifstream(views + "/session.json"));
  const auto largest_error = [&](const Calibration& c) {
    const auto motion = [&](const Calibration& of, const nlohmann::json& pose) {
      const auto& first = session["stage_poses"][0];
      return of.LFromCamera(Side::kLeft, first["pan_deg"], first["tilt_deg"]).inverse() *
             of.LFromCamera(Side::kLeft, pose["pan_deg"], pose["tilt_deg"]);
    };
    std::pair<double, double> worst{0.0, 0.0};
    for (const auto& pose : session["stage_poses"]) {
      const Eigen::Isometry3d e = motion(c, pose).inverse() * motion(*true_rig, pose);
      worst.first = std::max(worst.first, Eigen::AngleAxisd(e.linear()).angle() * 180 / M_PI);
      worst.second = std::max(worst.second, e.translation().norm());
    }
    return worst;
  };
  const auto before = largest_error(*calibrated), after = largest_error(*staged);
  std::printf("relative camera motions: %.4f deg, %.1f mm before; %.4f deg, %.1f mm after\n",
              before.first, 1e3 * before.second, after.first, 1e3 * after.second);
  EXPECT_GT(before.first, 0.1);
  EXPECT_LT(after.first, 0.01);
  EXPECT_LT(after.second, 0.002);

  // --refine-cameras: the cameras and the stereo pair refined with the stage, each observed by
  // the calibration calibrate stereo wrote, with its covariance. Written as report.json states
  // them, each with a sigma no wider than its calibration's (the adjustment adds information to
  // that prior), and the cameras' motions as close as before. (This session also calibrated the
  // cameras, so its images count twice here; rig_cameras_test checks the sigmas' honesty.)
  const std::string refined_out = dir / "refined.yaml";
  const auto refine = calibrate_rig(refined_out, " --refine-cameras");
  ASSERT_EQ(refine.exit_code, 0) << refine.out;
  const auto f = nlohmann::json::parse(refine.out);
  const Result<Calibration> refined = LoadCalibrationYaml(refined_out);
  ASSERT_TRUE(refined.ok()) << refined.error();
  const RigCameraVector given = RigCameraVectorOf(calibrated->rig),
                        written = RigCameraVectorOf(refined->rig);
  const RigCameraVector prior_sigma =
      RigCameraSigmas({true, calibrated->rig, calibrated->left_precision,
                       calibrated->right_precision, calibrated->stereo_precision});
  const RigCameraVector written_sigma =
      RigCameraSigmas({true, refined->rig, refined->left_precision, refined->right_precision,
                       refined->stereo_precision});
  int compared = 0;
  for (int i = 0; i < kRigCameraParameterCount; ++i) {
    const std::string name = RigCameraParameterName(i);
    const auto& p = f["cameras"][name];
    EXPECT_NEAR(p["value"].get<double>(), written[i], 1e-9 * std::abs(written[i]) + 1e-15) << name;
    EXPECT_NEAR(p["change"].get<double>(), written[i] - given[i], 1e-9 * std::abs(written[i]))
        << name;
    EXPECT_NEAR(p["sigma"].get<double>(), written_sigma[i], 1e-12 + 1e-6 * written_sigma[i]);
    if (p["held"].get<bool>()) {
      EXPECT_EQ(prior_sigma[i], 0.0) << name << ": held only where its calibration fixed it";
      continue;
    }
    ++compared;
    EXPECT_LE(written_sigma[i], prior_sigma[i]) << name;
  }
  EXPECT_GE(compared, 10);
  const auto refined_error = largest_error(*refined);
  EXPECT_LT(refined_error.first, 0.01);
  EXPECT_LT(refined_error.second, 0.002);

  const std::string camera_out = dir / "left.yaml";
  const auto one = RunCommand(kExe + " calibrate camera --images '" + views + "/left/*.png'" +
                              field + " --out " + camera_out + " --json 2>/dev/null");
  ASSERT_EQ(one.exit_code, 0) << one.out;
  const auto k = nlohmann::json::parse(one.out);
  EXPECT_NEAR(k["fy"].get<double>(), true_rig->rig.left.principal_distance_px,
              4 * k["sigma"]["c"].get<double>());
  EXPECT_TRUE(std::filesystem::exists(camera_out));
}

// The stereo pair: both cameras and the relative orientation, written as the calibration file
// process reads (schema 2, with the sigmas), the baseline in the unit of --square.
TEST(CalibrateCommand, StereoFromTheRealBoardsWritesACalibrationProcessReads) {
  testing::TempDir dir;
  const std::string out = dir / "cal.yaml";
  const auto r =
      RunCommand(kExe + " calibrate stereo --left '" + kBoards + "/left*.jpg' --right '" + kBoards +
                 "/right*.jpg' --square 0.025 --out " + out + " --json 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* side : {"left", "right"})
    for (const char* key : {"rms_px", "fx", "fy", "cx", "cy"})
      EXPECT_TRUE(j[side][key].is_number()) << side << "." << key;
  EXPECT_EQ(j["left"]["views_used"], 13);
  EXPECT_EQ(j["right"]["views_used"], 12);
  EXPECT_LT(j["stereo"]["rms_px"].get<double>(), 0.3);
  // OpenCV's sample views leave about half of the cells along the frame's edges empty (54 % and
  // 50 % measured): the distortion there is extrapolated, and the user is told.
  for (const char* side : {"left", "right"}) {
    EXPECT_LT(j[side]["coverage"]["border_share"].get<double>(), 0.75) << side;
    EXPECT_NE(j[side]["warnings"].dump().find("along the frame's edges"), std::string::npos)
        << side;
  }
  // The verdict says so: the stereo map is uncertain by pixels at the frame's edges.
  EXPECT_EQ(j["validation"]["verdict"], "needs views at the edges") << j["validation"]["reason"];
  EXPECT_GT(j["validation"]["maps"][0]["max_sigma_px"].get<double>(), 1.0);
  // The report beside the file: what --json printed, and the pictures.
  EXPECT_EQ(j["report"], dir / "cal.report");
  const auto report = nlohmann::json::parse(std::ifstream(dir / "cal.report/report.json"));
  EXPECT_EQ(report["validation"]["verdict"], j["validation"]["verdict"]);
  for (const char* picture : {"residuals_left.png", "histogram_right.png", "view_rms_left.png",
                              "coverage_right.png", "uncertainty.png"}) {
    const cv::Mat image = cv::imread(dir / (std::string("cal.report/") + picture));
    EXPECT_GT(image.cols, 300) << picture;
  }
  const double baseline = j["stereo"]["baseline"].get<double>();
  EXPECT_NEAR(baseline / 0.025, 3.32, 0.05) << "about 3.3 squares";
  const Result<Calibration> cal = LoadCalibrationYaml(out);
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_DOUBLE_EQ(cal->rig.baseline_m, baseline);
  EXPECT_DOUBLE_EQ(cal->rig.left.principal_distance_px, j["left"]["fy"].get<double>());
  ASSERT_TRUE(cal->stereo_precision.known);
  EXPECT_DOUBLE_EQ(cal->stereo_precision.baseline_sigma_m,
                   j["stereo"]["baseline_sigma"].get<double>());
  EXPECT_TRUE(cal->left_precision.known);
  EXPECT_DOUBLE_EQ(cal->left_precision.sigma[0], j["left"]["sigma"]["c"].get<double>());

  // Through OpenCV's FileStorage and back: the same rig, the conversion's difference said.
  const std::string opencv = dir / "stereo.yml", back = dir / "back.yaml";
  const auto e = RunCommand(kExe + " calibrate export-opencv --calibration " + out + " --out " +
                            opencv + " 2>&1");
  ASSERT_EQ(e.exit_code, 0) << e.out;
  EXPECT_NE(e.out.find("left: the two lens models project the frame alike within"),
            std::string::npos)
      << e.out;
  const auto i =
      RunCommand(kExe + " calibrate import-opencv --opencv " + opencv + " --out " + back + " 2>&1");
  ASSERT_EQ(i.exit_code, 0) << i.out;
  const Result<Calibration> imported = LoadCalibrationYaml(back);
  ASSERT_TRUE(imported.ok()) << imported.error();
  EXPECT_NEAR(imported->rig.baseline_m, cal->rig.baseline_m, 1e-9);
  EXPECT_TRUE(imported->rig.left_from_right.isApprox(cal->rig.left_from_right, 1e-9));
  EXPECT_NEAR(imported->rig.left.principal_distance_px, cal->rig.left.principal_distance_px, 3.0);
  const auto neither = RunCommand(kExe + " calibrate export-opencv --out " + opencv + " 2>&1");
  EXPECT_EQ(neither.exit_code, 1);
  EXPECT_NE(neither.out.find("give one of --calibration and --camera"), std::string::npos);
}

// --stage-from: the stage kinematics come from the previous calibration, the rig's baseline
// and cameras from the boards; a file that cannot be read stops the command before the work.
TEST(CalibrateCommand, StereoKeepsTheStageOfThePreviousCalibration) {
  testing::TempDir dir;
  const std::string previous = dir / "previous.yaml", out = dir / "cal.yaml";
  Calibration old;
  old.rig.left = old.rig.right = CameraIntrinsics{640, 480, 0.0, 530.0, 320.0, 240.0};
  old.rig.baseline_m = 0.08;
  old.stage.height_above_mark_m = 1.37;
  old.stage.pan_zero_deg = 2.5;
  ASSERT_TRUE(SaveCalibrationYaml(old, previous).ok());
  const std::string command = kExe + " calibrate stereo --left '" + kBoards +
                              "/left*.jpg' --right '" + kBoards +
                              "/right*.jpg' --square 0.025 --out " + out + " --stage-from ";
  const auto missing = RunCommand(command + (dir / "none.yaml") + " 2>&1");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.out.find("--stage-from: "), std::string::npos) << missing.out;
  EXPECT_EQ(missing.out.find("no 9x6 chessboard"), std::string::npos) << "stopped before detection";
  const auto r = RunCommand(command + previous + " 2>/dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const Result<Calibration> cal = LoadCalibrationYaml(out);
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_DOUBLE_EQ(cal->stage.height_above_mark_m, 1.37);
  EXPECT_DOUBLE_EQ(cal->stage.pan_zero_deg, 2.5);
  EXPECT_NEAR(cal->rig.baseline_m / 0.025, 3.32, 0.05) << "the baseline from the boards";
}

TEST(CalibrateCommand, StereoViewsThatCannotBePairedAreOneClearError) {
  testing::TempDir dir;
  const std::string out = dir / "cal.yaml";
  const auto r =
      RunCommand(kExe + " calibrate stereo --left '" + kBoards + "/left0*.jpg' --right '" +
                 kBoards + "/right*.jpg' --out " + out + " 2>&1");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("--right: 13 images, --left has 9"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CalibrateCommand, BadInputIsOneClearErrorAndNoFile) {
  testing::TempDir dir;
  const std::string out = dir / "cal.yaml";
  std::ofstream(dir / "broken.jpg") << "not an image";
  const struct {
    std::string args, expect;
  } cases[] = {
      {"--images '" + (dir / "none*.png") + "'", "--images: no file matches"},
      {"--images '" + (dir / "broken.jpg") + "'", "broken.jpg: not a readable image"},
      {"--images '" + kBoards + "/left*.jpg' --chessboard 9by6", "--chessboard: expected"},
      {"--images '" + kBoards + "/left*.jpg' --chessboard 7x5", "is the board size right?"},
      {"--images '" + kBoards + "/left0[12].jpg'", "at least 3 views"},
  };
  for (const auto& c : cases) {
    const auto r = RunCommand(kExe + " calibrate camera " + c.args + " --out " + out + " 2>&1");
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
}

// A field file with a NaN or a duplicate id, marks without a field's targets, a missing flag:
// each one clear error naming the file and the field, and no calibration written.
TEST(CalibrateCommand, BadControlFieldIsOneClearErrorAndNoFile) {
  testing::TempDir dir;
  const std::string views = dir / "field", out = dir / "cal.yaml";
  const auto render = RunCommand(kExe + " sim render --calibration field --field-pans 1 " +
                                 "--field-tilts 1 --out " + views + " --truth " + (dir / "t"));
  ASSERT_EQ(render.exit_code, 0) << render.out;
  std::string targets;
  for (int id = 1; id <= 6; ++id)
    targets += "    - {id: " + std::to_string(id) +
               ", x: 1, y: 2, z: 3, sigma_m: 0.001, "
               "diameter_m: 0.1}\n";
  const std::string head = "control_field:\n  version: 1\n  targets:\n";
  std::ofstream(dir / "nan.yaml") << head << targets
                                  << "    - {id: 7, x: .nan, y: 2, z: 3, sigma_m: 0.001, "
                                     "diameter_m: 0.1}\n";
  std::ofstream(dir / "twice.yaml") << head << targets
                                    << "    - {id: 3, x: 1, y: 2, z: 3, sigma_m: 0.001, "
                                       "diameter_m: 0.1}\n";
  std::ofstream(dir / "marks.yaml") << "marks:\n  - image: left/01.png\n    targets: "
                                       "[{id: 5, x: 1, y: .inf}]\n";
  const std::string images = " --images '" + views + "/left/*.png'";
  const std::string rest = " --marks " + views + "/marks.yaml --start " + views + "/design.yaml";
  const struct {
    std::string args, expect;
  } cases[] = {
      {images + " --control-field " + (dir / "nan.yaml") + rest,
       "nan.yaml: control_field.targets[6].x: must be finite"},
      {images + " --control-field " + (dir / "twice.yaml") + rest,
       "twice.yaml: control_field.targets[6].id: 3 twice"},
      {images + " --control-field " + views + "/field.yaml --marks " + (dir / "marks.yaml") +
           " --start " + views + "/design.yaml",
       "marks.yaml: marks[0].targets[0].y: must be finite"},
      {images + " --control-field " + views + "/field.yaml --start " + views + "/design.yaml",
       "give --marks"},
      {images + " --control-field " + views + "/field.yaml --chessboard 9x6" + rest, "excludes"},
  };
  for (const auto& c : cases) {
    const auto r = RunCommand(kExe + " calibrate camera" + c.args + " --out " + out + " 2>&1");
    EXPECT_NE(r.exit_code, 0) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
}

// Two stations of one rig (rendered hills and rough ground, the rig's true cameras, its stage
// at the design values): one adjustment closes the seams of both, gives each its levelling,
// and brings the stage's angles within their sigmas of the truth.
TEST(CalibrateRigCommand, TwoStationsOfOneRigInOneAdjustment) {
  testing::TempDir dir;
  std::vector<std::string> stations;
  for (const std::string scene : {"hills", "rough"}) {
    const std::string st = dir / scene;
    const auto r = RunCommand(kExe + " sim render --scene " + scene + " --seed 3 --out " + st +
                              " --truth " + st + "-truth 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    stations.push_back(st);
  }
  const Result<Calibration> truth = LoadCalibrationYaml(stations[0] + "-truth/calibration.yaml");
  ASSERT_TRUE(truth.ok()) << truth.error();
  const Result<StationManifest> manifest = LoadStationManifest(stations[0]);
  ASSERT_TRUE(manifest.ok()) << manifest.error();
  Calibration design = *truth;
  design.stage = manifest->calibration.stage;
  ASSERT_TRUE(SaveCalibrationYaml(design, dir / "design.yaml").ok());
  const std::string out = dir / "rig.yaml";
  const auto r =
      RunCommand(kExe + " calibrate rig " + stations[0] + " " + stations[1] + " --calibration " +
                 (dir / "design.yaml") + " --out " + out + " --json 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["seams"]["before"]["within_2_sigma"].get<double>(), 0.9);
  ASSERT_EQ(j["stations"].size(), 2u);
  const Result<Calibration> estimated = LoadCalibrationYaml(out);
  ASSERT_TRUE(estimated.ok()) << estimated.error();
  // The truth's levelling in the estimate's gauge: L's Y is the held pan zero's direction, so
  // the levelling turns with the pan zero's difference (the readings' model, inclinometer.h).
  const double turn =
      (estimated->stage.pan_zero_deg - truth->stage.pan_zero_deg) * std::numbers::pi / 180.0;
  const Eigen::Vector2d true_levelling =
      Eigen::Rotation2Dd(turn) *
      Eigen::Vector2d(truth->stage.levelling_x_deg, truth->stage.levelling_y_deg);
  for (const auto& station : j["stations"]) {
    EXPECT_GE(station["seams_after"]["within_2_sigma"].get<double>(), 0.9) << station;
    // The levelling is the inclinometer's (the seams do not see which way is down), fitted to
    // its readings round the pan: the index error (0.02 deg) gone, the sigma the readings'
    // noise (0.002 deg) over sqrt(6).
    EXPECT_EQ(station["inclinometer"]["fitted_round_the_pan"], true) << station;
    for (int axis : {0, 1}) {
      const nlohmann::json& levelling = station[axis == 0 ? "levelling_x_deg" : "levelling_y_deg"];
      const double sigma = levelling["sigma"].get<double>();
      EXPECT_LT(sigma, 0.0015) << station;
      EXPECT_NEAR(levelling["value"].get<double>(), true_levelling[axis], 4 * sigma) << axis;
    }
  }
  const StageVector e = StageVectorOf(estimated->stage), t = StageVectorOf(truth->stage);
  // The tilt axis's skew and the rig's phi and kappa within 4 of their sigma; the tilt zero and
  // the rig's omega turn the views about one axis: their difference within 0.01 deg.
  for (int i : {7, 12, 13}) {
    const double sigma = j["parameters"][kStageParameterNames[i]]["sigma"].get<double>();
    ASSERT_GT(sigma, 0.0) << kStageParameterNames[i];
    EXPECT_LT(std::abs(e[i] - t[i]), 4 * sigma) << kStageParameterNames[i];
  }
  EXPECT_NEAR(e[11] - e[3], t[11] - t[3], 0.01);
  EXPECT_TRUE(std::filesystem::exists(dir / "rig.report/seams.png"));
}

// calibrate rig refuses what it cannot tie, with one line naming the station, and writes
// nothing: a station given twice (its tie points would count double), a station of one pair,
// nothing to adjust, a field session without its field, a field session's bad poses.
TEST(CalibrateRigCommand, WhatCannotBeTiedIsOneClearErrorAndNothingIsWritten) {
  testing::TempDir dir;
  const std::string station = dir / "one-pair", out = dir / "rig.yaml";
  const StationManifest m = testing::MakeStation(station, 12, 1);
  ASSERT_TRUE(SaveCalibrationYaml(m.calibration, dir / "cal.yaml").ok());
  const std::string common = " --calibration " + (dir / "cal.yaml") + " --out " + out + " 2>&1";
  const auto two = RunCommand(kExe + " calibrate rig " + station + " " + station + "/" + common);
  EXPECT_NE(two.exit_code, 0);
  EXPECT_NE(two.out.find("given twice"), std::string::npos) << two.out;
  const auto one = RunCommand(kExe + " calibrate rig " + station + common);
  EXPECT_NE(one.exit_code, 0);
  EXPECT_NE(one.out.find(station + ": fewer than two pairs"), std::string::npos) << one.out;
  // A field session needs its field and marks, and must be one: each a line naming what.
  const auto none = RunCommand(kExe + " calibrate rig" + common);
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.out.find("give a captured STATION, or a --field-session"), std::string::npos)
      << none.out;
  const auto no_field = RunCommand(kExe + " calibrate rig --field-session " + station + common);
  EXPECT_NE(no_field.exit_code, 0);
  EXPECT_NE(no_field.out.find("--field-session: give --control-field"), std::string::npos)
      << no_field.out;
  std::ofstream(dir / "session.json") << "{\"stage_poses\": [{\"image\": \"01.png\"}]}";
  std::ofstream(dir / "field.yaml") << "control_field:\n  version: 1\n  targets: []\n";
  const auto bad = RunCommand(kExe + " calibrate rig --field-session " + dir.path().string() +
                              " --control-field " + (dir / "field.yaml") + " --marks " +
                              (dir / "field.yaml") + common);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("session.json: stage_poses[0]: needs image, pan_deg and tilt_deg"),
            std::string::npos)
      << bad.out;
  // Design cameras carry no precision to weigh them by: they cannot be refined.
  const auto design = RunCommand(kExe + " calibrate rig " + station + " --refine-cameras" + common);
  EXPECT_NE(design.exit_code, 0);
  EXPECT_NE(design.out.find(dir / "cal.yaml: cameras.left: no precision"), std::string::npos)
      << design.out;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace ts
