#include "acquisition/rig_config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

TEST(RigConfig, LoadsTheExampleRig) {
  const Result<RigConfig> rig = LoadRigConfig(TS_SOURCE_DIR "/config/rig.example.yaml");
  ASSERT_TRUE(rig.ok()) << rig.error();
  EXPECT_EQ(rig->name, "paper-rig");
  EXPECT_DOUBLE_EQ(rig->calibration.rig.baseline_m, 0.5);
  EXPECT_NEAR(rig->calibration.rig.left.principal_distance_px, 1860.465, 1e-3);
  EXPECT_EQ(rig->stage.transport, StageTransport::kRtu);
  EXPECT_EQ(rig->stage.device, "/dev/topostation-stage");
  EXPECT_EQ(rig->left_camera.id, "TS-LEFT-0001");
  std::string why;
  EXPECT_TRUE(rig->calibration.Check(&why)) << why;
}

constexpr const char* kCalibration = R"(schema_version: 1
cameras:
  left: {width_px: 100, height_px: 80, principal_distance_px: 120}
  right: {width_px: 100, height_px: 80, principal_distance_px: 120}
stereo: {baseline_m: 0.4}
)";

std::string Rig(const std::string& stage, const std::string& calibration_line) {
  return "schema_version: 1\nname: t\ndevices:\n  left_camera: {id: L}\n  right_camera: {id: "
         "R}\n  stage: " +
         stage + "\n" + calibration_line + "\n";
}

TEST(RigConfig, ReadsAnExternalCalibrationFileRelativeToTheRig) {
  testing::TempDir dir;
  std::ofstream(dir / "cal.yaml") << kCalibration;
  std::ofstream(dir / "rig.yaml") << Rig("{transport: tcp, host: 127.0.0.1, port: 15020}",
                                         "calibration_file: cal.yaml");
  const Result<RigConfig> rig = LoadRigConfig(dir / "rig.yaml");
  ASSERT_TRUE(rig.ok()) << rig.error();
  EXPECT_DOUBLE_EQ(rig->calibration.rig.baseline_m, 0.4);
  EXPECT_EQ(rig->stage.port, 15020);
  EXPECT_EQ(rig->stage.unit_id, 1);
  EXPECT_TRUE(rig->stage.inclinometer_turns_with_pan);  // topostation's stage: on the pan
  std::ofstream(dir / "base.yaml")
      << Rig("{transport: tcp, host: 127.0.0.1, port: 15020, inclinometer: base}",
             "calibration_file: cal.yaml");
  const Result<RigConfig> base = LoadRigConfig(dir / "base.yaml");
  ASSERT_TRUE(base.ok()) << base.error();
  EXPECT_FALSE(base->stage.inclinometer_turns_with_pan);
}

struct BadRig {
  const char* name;
  std::string text;
  const char* expect;
};

void PrintTo(const BadRig& r, std::ostream* os) { *os << r.name; }

class RigConfigBad : public ::testing::TestWithParam<BadRig> {};

TEST_P(RigConfigBad, GivesOneClearError) {
  testing::TempDir dir;
  std::ofstream(dir / "cal.yaml") << kCalibration;
  std::ofstream(dir / "broken-cal.yaml") << "schema_version: 1\ncameras: {}\n";
  std::ofstream(dir / "rig.yaml") << GetParam().text;
  const Result<RigConfig> rig = LoadRigConfig(dir / "rig.yaml");
  ASSERT_FALSE(rig.ok());
  EXPECT_NE(rig.error().find(GetParam().expect), std::string::npos) << rig.error();
  EXPECT_EQ(rig.error().find('\n'), std::string::npos);
}

const std::string kTcp = "{transport: tcp, host: 127.0.0.1, port: 15020}";

INSTANTIATE_TEST_SUITE_P(
    Cases, RigConfigBad,
    ::testing::Values(
        BadRig{"transport", Rig("{transport: can, host: x, port: 1}", "calibration_file: cal.yaml"),
               "rig.yaml: devices.stage.transport: must be tcp or rtu"},
        BadRig{"port", Rig("{transport: tcp, host: x, port: 70000}", "calibration_file: cal.yaml"),
               "devices.stage.port: must be in [1, 65535]"},
        BadRig{"rtu_without_device", Rig("{transport: rtu}", "calibration_file: cal.yaml"),
               "devices.stage.device: missing"},
        BadRig{"inclinometer",
               Rig("{transport: tcp, host: x, port: 1, inclinometer: tilt}",
                   "calibration_file: cal.yaml"),
               "devices.stage.inclinometer: must be pan (it turns with the pan) or base, got "
               "'tilt'"},
        BadRig{"no_calibration", Rig(kTcp, ""), "give exactly one of calibration"},
        BadRig{"missing_calibration_file", Rig(kTcp, "calibration_file: nope.yaml"),
               "nope.yaml: cannot read file"},
        BadRig{"broken_calibration_file", Rig(kTcp, "calibration_file: broken-cal.yaml"),
               "broken-cal.yaml: cameras.left: missing"},
        BadRig{"inline_nan",
               Rig(kTcp,
                   "calibration: {schema_version: 1, cameras: {left: {width_px: 10, "
                   "height_px: 10, principal_distance_px: .nan}}}"),
               "rig.yaml: calibration.cameras.left.principal_distance_px: must be finite"},
        BadRig{"unknown", Rig(kTcp, "calibration_file: cal.yaml\ncolour: blue"),
               "colour: unknown key"}),
    [](const ::testing::TestParamInfo<BadRig>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace ts
