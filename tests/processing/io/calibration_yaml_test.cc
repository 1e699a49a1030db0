#include "processing/io/calibration_yaml.h"

#include <gtest/gtest.h>

#include <fstream>

#include "processing/geometry/rotation.h"
#include "processing/io/atomic_file.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

Calibration Example() {
  Calibration cal;
  CameraIntrinsics c;
  c.width_px = 1392;
  c.height_px = 1040;
  c.pixel_size_um = 6.45;
  c.principal_distance_px = 1861.234567890123;
  c.principal_point_x_px = 700.125;
  c.principal_point_y_px = 515.5;
  c.k1 = -0.123456789;
  c.k2 = 0.0456;
  c.k3 = -1e-3;
  c.p1 = 1.5e-4;
  c.p2 = -2.5e-4;
  c.scale_x = 1e-4;
  c.shear = -3e-5;
  cal.rig.left = c;
  c.principal_distance_px = 1858.5;
  c.k1 = -0.11;
  cal.rig.right = c;
  cal.rig.baseline_m = 0.5012;
  cal.rig.S_from_left = StereoRig::NominalSFromCamera() * RotationFromOpk({0.002, -0.01, 0.003});
  cal.rig.left_from_right = RotationFromOpk({0.001, 0.02, -0.004});
  cal.stage.height_above_mark_m = 1.45;
  cal.stage.levelling_x_deg = 0.12;
  cal.stage.levelling_y_deg = -0.08;
  cal.stage.pan_zero_deg = 3.25;
  cal.stage.tilt_zero_deg = -0.5;
  cal.stage.tilt_axis_offset_m = {0.001, 0.02, 0.15};
  cal.stage.tilt_axis_skew_deg = 0.03;
  cal.stage.rig_offset_m = {0.0, 0.03, 0.08};
  cal.stage.rig_rotation_opk_deg = {0.1, -0.05, 0.2};
  return cal;
}

void ExpectSameCamera(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  EXPECT_EQ(a.width_px, b.width_px);
  EXPECT_EQ(a.height_px, b.height_px);
  const auto pa = a.ToParameters(), pb = b.ToParameters();
  for (size_t i = 0; i < pa.size(); ++i) EXPECT_DOUBLE_EQ(pa[i], pb[i]) << i;
}

TEST(CalibrationYaml, RoundTripsEveryParameter) {
  testing::TempDir dir;
  const Calibration cal = Example();
  ASSERT_TRUE(SaveCalibrationYaml(cal, dir / "cal.yaml").ok());
  const Result<Calibration> back = LoadCalibrationYaml(dir / "cal.yaml");
  ASSERT_TRUE(back.ok()) << back.error();
  ExpectSameCamera(back->rig.left, cal.rig.left);
  ExpectSameCamera(back->rig.right, cal.rig.right);
  EXPECT_DOUBLE_EQ(back->rig.baseline_m, cal.rig.baseline_m);
  EXPECT_TRUE(back->rig.S_from_left.isApprox(cal.rig.S_from_left, 1e-14));
  EXPECT_TRUE(back->rig.left_from_right.isApprox(cal.rig.left_from_right, 1e-14));
  for (double pan : {0.0, 123.0}) {
    EXPECT_TRUE(
        back->stage.LFromS(pan, -20).matrix().isApprox(cal.stage.LFromS(pan, -20).matrix(), 1e-14));
  }
  EXPECT_DOUBLE_EQ(back->stage.height_above_mark_m, 1.45);
}

// Schema 2: each camera's sigmas and covariance, the stereo sigmas and covariance, the RMS.
TEST(CalibrationYaml, RoundTripsThePrecisionOfACalibration) {
  testing::TempDir dir;
  Calibration cal = Example();
  cal.left_precision.known = true;
  for (int i = 0; i < CameraIntrinsics::kNumParameters; ++i) {
    cal.left_precision.sigma[i] = 0.01 * (i + 1);
    for (int j = 0; j < CameraIntrinsics::kNumParameters; ++j)
      cal.left_precision.covariance(i, j) = 1e-4 * (i == j ? 2.0 : 0.5) / (1 + i + j);
  }
  cal.left_precision.rms_px = 0.21;
  cal.stereo_precision = {true, 1.5e-4, {0.002, 0.003, 0.001}, Eigen::Matrix4d::Identity() * 1e-6,
                          0.25, {}};
  ASSERT_TRUE(SaveCalibrationYaml(cal, dir / "cal.yaml").ok());
  const Result<Calibration> back = LoadCalibrationYaml(dir / "cal.yaml");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_TRUE(back->left_precision.known);
  EXPECT_FALSE(back->right_precision.known) << "design values have no precision";
  EXPECT_EQ(back->left_precision.sigma, cal.left_precision.sigma);
  EXPECT_EQ(back->left_precision.covariance, cal.left_precision.covariance);
  EXPECT_DOUBLE_EQ(back->left_precision.rms_px, 0.21);
  EXPECT_DOUBLE_EQ(back->stereo_precision.baseline_sigma_m, 1.5e-4);
  EXPECT_EQ(back->stereo_precision.relative_sigma_deg, cal.stereo_precision.relative_sigma_deg);
  EXPECT_EQ(back->stereo_precision.covariance, cal.stereo_precision.covariance);
  ExpectSameCamera(back->rig.left, cal.rig.left);
}

// The cameras' and the pair's covariance jointly (calibrate stereo's one adjustment): kept
// whole, its diagonal blocks the three covariances; one that contradicts them is refused.
TEST(CalibrationYaml, RoundTripsTheJointCovarianceAndChecksItsBlocks) {
  testing::TempDir dir;
  constexpr int kN = CameraIntrinsics::kNumParameters, kJoint = 2 * kN + 4;
  Calibration cal = Example();
  Eigen::MatrixXd joint = Eigen::MatrixXd::Zero(kJoint, kJoint);
  for (int i = 0; i < kJoint; ++i)
    for (int j = 0; j < kJoint; ++j)
      joint(i, j) = 1e-6 * (i == j ? 4.0 : 1.0 / (1 + std::abs(i - j)));
  cal.left_precision.known = cal.right_precision.known = cal.stereo_precision.known = true;
  cal.left_precision.covariance = joint.block(0, 0, kN, kN);
  cal.right_precision.covariance = joint.block(kN, kN, kN, kN);
  cal.stereo_precision.covariance = joint.block(2 * kN, 2 * kN, 4, 4);
  cal.stereo_precision.joint_covariance = joint;
  ASSERT_TRUE(SaveCalibrationYaml(cal, dir / "cal.yaml").ok());
  const Result<Calibration> back = LoadCalibrationYaml(dir / "cal.yaml");
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->stereo_precision.joint_covariance, joint);

  cal.right_precision.covariance(0, 0) *= 2.0;
  ASSERT_TRUE(SaveCalibrationYaml(cal, dir / "cal.yaml").ok());
  const Result<Calibration> contradicted = LoadCalibrationYaml(dir / "cal.yaml");
  ASSERT_FALSE(contradicted.ok());
  EXPECT_NE(contradicted.error().find("stereo.joint_covariance: its diagonal blocks are not"),
            std::string::npos)
      << contradicted.error();
  EXPECT_NE(contradicted.error().find("cal.yaml"), std::string::npos) << contradicted.error();

  std::ofstream(dir / "short.yaml")
      << "schema_version: 3\ncameras:\n  left: {width_px: 10, height_px: 10, "
         "principal_distance_px: 10}\n  right: {width_px: 10, height_px: 10, "
         "principal_distance_px: 10}\nstereo: {baseline_m: 0.5, sigma: {baseline_m: 0.001}, "
         "covariance: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], joint_covariance: [1, "
         "2]}\n";
  const Result<Calibration> short_joint = LoadCalibrationYaml(dir / "short.yaml");
  ASSERT_FALSE(short_joint.ok());
  EXPECT_NE(short_joint.error().find("stereo.joint_covariance: must be a list of 576"),
            std::string::npos)
      << short_joint.error();

  // Written as schema 3, the lowest that holds it; without it, as schema 2 (builds before the
  // joint covariance read it). Schema 2 does not know the key.
  const auto ReadFile = [](const std::string& file) {
    const Result<std::string> text = ReadWholeFile(file);
    EXPECT_TRUE(text.ok()) << file;
    return text.ok() ? *text : std::string();
  };
  EXPECT_NE(ReadFile(dir / "cal.yaml").find("schema_version: 3"), std::string::npos);
  cal.stereo_precision.joint_covariance.resize(0, 0);
  ASSERT_TRUE(SaveCalibrationYaml(cal, dir / "plain.yaml").ok());
  EXPECT_NE(ReadFile(dir / "plain.yaml").find("schema_version: 2"), std::string::npos);
  std::string two = ReadFile(dir / "short.yaml");
  two.replace(two.find("schema_version: 3"), 17, "schema_version: 2");
  std::ofstream(dir / "two.yaml") << two;
  const Result<Calibration> in_two = LoadCalibrationYaml(dir / "two.yaml");
  ASSERT_FALSE(in_two.ok());
  EXPECT_NE(in_two.error().find("stereo.joint_covariance: unknown key"), std::string::npos)
      << in_two.error();
}

TEST(CalibrationYaml, PrecisionIsCheckedAndBelongsToSchemaTwo) {
  testing::TempDir dir;
  const std::string cameras =
      "cameras:\n  right: {width_px: 10, height_px: 10, principal_distance_px: 10}\n"
      "  left: {width_px: 10, height_px: 10, principal_distance_px: 10, ";
  const std::string sigma =
      "sigma: {c: 1, xp: 1, yp: 1, k1: 0, k2: 0, k3: 0, p1: 0, p2: 0, scale_x: 0, shear: 0}";
  const struct {
    std::string text, expect;
  } cases[] = {
      {"schema_version: 1\n" + cameras + sigma + "}\nstereo: {baseline_m: 0.5}\n",
       "cameras.left.sigma: unknown key"},
      {"schema_version: 2\n" + cameras + sigma +
           ", covariance: [1, 2]}\nstereo: {baseline_m: 0.5}\n",
       "cameras.left.covariance: must be a list of 100"},
      {"schema_version: 2\n" + cameras + "sigma: {c: -1}}\nstereo: {baseline_m: 0.5}\n",
       "cameras.left.sigma.c: must be >= 0"},
  };
  for (const auto& c : cases) {
    std::ofstream(dir / "cal.yaml") << c.text;
    const Result<Calibration> cal = LoadCalibrationYaml(dir / "cal.yaml");
    ASSERT_FALSE(cal.ok()) << c.text;
    EXPECT_NE(cal.error().find(c.expect), std::string::npos) << cal.error();
  }
}

TEST(CalibrationYaml, FocalLengthInMillimetresAndDefaultPrincipalPoint) {
  testing::TempDir dir;
  std::ofstream(dir / "cal.yaml") << R"(schema_version: 1
cameras:
  left: {width_px: 1392, height_px: 1040, pixel_size_um: 6.45, principal_distance_mm: 12}
  right: {width_px: 1392, height_px: 1040, pixel_size_um: 6.45, principal_distance_mm: 12}
stereo: {baseline_m: 0.5}
)";
  const Result<Calibration> cal = LoadCalibrationYaml(dir / "cal.yaml");
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_NEAR(cal->rig.left.principal_distance_px, 12000.0 / 6.45, 1e-9);
  EXPECT_DOUBLE_EQ(cal->rig.left.principal_point_x_px, 695.5);
  EXPECT_DOUBLE_EQ(cal->rig.left.principal_point_y_px, 519.5);
  EXPECT_TRUE(cal->rig.S_from_left.isApprox(StereoRig::NominalSFromCamera()));
}

struct BadCase {
  const char* name;
  const char* find;     // text to replace in the good document ("" = replace all)
  const char* replace;  // with this
  const char* expect;   // the error must contain this
};

constexpr const char* kGood = R"(schema_version: 1
cameras:
  left: {width_px: 1392, height_px: 1040, principal_distance_px: 1860, principal_point_px: [695.5, 519.5]}
  right: {width_px: 1392, height_px: 1040, principal_distance_px: 1860}
stereo: {baseline_m: 0.5, right_relative_opk_deg: [0, 0, 0]}
stage: {height_above_mark_m: 1.5, levelling_deg: [0.1, 0.2]}
)";

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class CalibrationYamlBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(CalibrationYamlBad, GivesOneClearErrorNamingFileAndField) {
  const BadCase& c = GetParam();
  std::string text = kGood;
  if (std::string(c.find).empty()) {
    text = c.replace;
  } else {
    const size_t at = text.find(c.find);
    ASSERT_NE(at, std::string::npos) << c.find;
    text.replace(at, std::string(c.find).size(), c.replace);
  }
  testing::TempDir dir;
  const std::string file = dir / "cal.yaml";
  std::ofstream(file) << text;
  const Result<Calibration> cal = LoadCalibrationYaml(file);
  ASSERT_FALSE(cal.ok()) << c.name;
  EXPECT_EQ(cal.error().rfind(file + ": ", 0), 0u) << cal.error();
  EXPECT_NE(cal.error().find(c.expect), std::string::npos) << cal.error();
  EXPECT_EQ(cal.error().find('\n'), std::string::npos) << "one line";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CalibrationYamlBad,
    ::testing::Values(
        BadCase{"nan", "principal_distance_px: 1860,", "principal_distance_px: .nan,",
                "cameras.left.principal_distance_px: must be finite"},
        BadCase{"missing", "baseline_m: 0.5, ", "", "stereo.baseline_m: missing"},
        BadCase{"negative", "baseline_m: 0.5", "baseline_m: -0.5",
                "stereo.baseline_m: must be positive"},
        BadCase{"unknown key", "height_px: 1040, principal_distance_px: 1860}",
                "height_px: 1040, principal_distanse_px: 1860}",
                "cameras.right.principal_distanse_px: unknown key"},
        BadCase{"not a number", "width_px: 1392, height_px: 1040, principal_distance_px: 1860,",
                "width_px: wide, height_px: 1040, principal_distance_px: 1860,",
                "cameras.left.width_px: must be an integer"},
        BadCase{"version", "schema_version: 1", "schema_version: 7",
                "schema_version: unsupported version 7"},
        BadCase{"list length", "principal_point_px: [695.5, 519.5]", "principal_point_px: [695.5]",
                "cameras.left.principal_point_px: must be a list"},
        BadCase{"levelling nan", "levelling_deg: [0.1, 0.2]", "levelling_deg: [0.1, .nan]",
                "stage.levelling_deg: element 1 must be a finite number"},
        BadCase{"both focal lengths", "principal_distance_px: 1860}",
                "principal_distance_px: 1860, principal_distance_mm: 12}",
                "give exactly one of _px and _mm"},
        BadCase{"syntax", "stereo: {baseline_m", "stereo: [baseline_m", "line "},
        // Finite but no real rig: each was accepted and gave confident nonsense or a crash.
        BadCase{"huge baseline", "baseline_m: 0.5", "baseline_m: 1e308",
                "stereo: baseline_m must be 0.01 to 10 m, got 1e+308"},
        BadCase{"tiny baseline", "baseline_m: 0.5", "baseline_m: 1e-300",
                "stereo: baseline_m must be 0.01 to 10 m"},
        BadCase{"no real lens", "principal_point_px: [695.5, 519.5]}",
                "principal_point_px: [695.5, 519.5], distortion: {k1: 1e6}}",
                "cameras.left: distortion and affinity move the image's corner by"},
        BadCase{"principal point off the image", "principal_point_px: [695.5, 519.5]",
                "principal_point_px: [2695.5, 519.5]", "cameras.left: principal point (2695.5"},
        BadCase{"telescope", "principal_distance_px: 1860, principal_point_px",
                "principal_distance_px: 1e6, principal_point_px",
                "gives a field of view outside 1-170 deg"},
        BadCase{"mast", "height_above_mark_m: 1.5", "height_above_mark_m: 1e308",
                "stage: height_above_mark_m must be 0 to 10 m"},
        BadCase{"empty", "", "", "file is empty"},
        BadCase{"not a mapping", "", "- 1\n- 2\n", "document: must be a mapping"}),
    [](const ::testing::TestParamInfo<BadCase>& info) {
      std::string name = info.param.name;
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

TEST(CalibrationYaml, MissingFileIsAnError) {
  const Result<Calibration> cal = LoadCalibrationYaml("/nonexistent/cal.yaml");
  ASSERT_FALSE(cal.ok());
  EXPECT_NE(cal.error().find("/nonexistent/cal.yaml: cannot read file"), std::string::npos);
}

}  // namespace
}  // namespace ts
