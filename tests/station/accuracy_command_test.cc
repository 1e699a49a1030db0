// Runs the real `topostation accuracy` binary, as a user would.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

const std::string kTopostation = TS_TOPOSTATION_EXE;
const std::string kRig = TS_SOURCE_DIR "/config/rig.example.yaml";

TEST(AccuracyCommand, JsonRowsForThePaperRig) {
  testing::TempDir dir;
  const std::string plot = dir / "accuracy.png";
  const auto r =
      testing::RunCommand(kTopostation + " accuracy --rig " + kRig + " --json --plot " + plot);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const nlohmann::json doc = nlohmann::json::parse(r.out);
  const auto& rows = doc.at("rows");
  ASSERT_EQ(rows.size(), 12u);
  for (size_t i = 0; i < rows.size(); ++i) {
    const double range = rows[i].at("range_m");
    EXPECT_DOUBLE_EQ(range, 5.0 * (i + 1));
    const double sy = rows[i].at("sigma_y_m");
    if (range == 30.0) {
      EXPECT_NEAR(sy, 0.32, 0.005);
    }
    if (range <= 50.0) {
      EXPECT_LT(sy, 1.0);
    }
    EXPECT_GT(rows[i].at("sigma_x_m").get<double>(), 0.0);
    EXPECT_GT(rows[i].at("sigma_z_m").get<double>(), 0.0);
  }
  const cv::Mat png = cv::imread(plot);
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.cols, 900);
}

TEST(AccuracyCommand, PrintsATable) {
  testing::TempDir dir;
  const auto r =
      testing::RunCommand(kTopostation + " accuracy --rig " + kRig + " --plot " + (dir / "p.png"));
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("sigma_y_m"), std::string::npos);
  EXPECT_NE(r.out.find("     30.0       "), std::string::npos) << r.out;
}

TEST(AccuracyCommand, BadRigGivesOneLineOnStderrAndNonZeroExit) {
  testing::TempDir dir;
  const std::string rig = dir / "bad.yaml";
  { std::ofstream(rig) << "schema_version: 1\nname: x\n"; }
  const auto r = testing::RunCommand(kTopostation + " accuracy --rig " + rig + " 2>&1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.out, "topostation: " + rig + ": devices: missing\n");
  const auto missing = testing::RunCommand(kTopostation + " accuracy --rig /no/such.yaml 2>&1");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.out.find("/no/such.yaml: cannot read file"), std::string::npos);
}

}  // namespace
}  // namespace ts
