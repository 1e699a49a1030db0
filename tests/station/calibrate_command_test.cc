// topostation calibrate camera on the real chessboard views, and its bad inputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "processing/io/calibration_yaml.h"
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

}  // namespace
}  // namespace ts
