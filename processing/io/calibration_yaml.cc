#include "processing/io/calibration_yaml.h"

#include <yaml-cpp/yaml.h>

#include "processing/geometry/rotation.h"
#include "processing/io/atomic_file.h"

namespace ts {
namespace {

constexpr int kN = CameraIntrinsics::kNumParameters;

// sigma: {c: .., xp: .., ...}, covariance: [row-major kN x kN], rms_px (schema 2).
CameraPrecision ParseCameraPrecision(YamlMap& m) {
  CameraPrecision p;
  if (!m.Has("sigma")) return p;
  p.known = true;
  YamlMap sigma = m.Map("sigma");
  for (int i = 0; i < kN; ++i) {
    p.sigma[i] = sigma.Double(CameraIntrinsics::kParameterNames[i]);
    if (!(p.sigma[i] >= 0.0)) sigma.Fail(CameraIntrinsics::kParameterNames[i], "must be >= 0");
  }
  sigma.RejectUnknownKeys();
  const std::vector<double> c = m.Doubles("covariance", kN * kN);
  for (int i = 0; i < kN * kN; ++i) p.covariance(i / kN, i % kN) = c[i];
  if (!p.covariance.isApprox(p.covariance.transpose(), 1e-9) ||
      (p.covariance.diagonal().array() < 0.0).any())
    m.Fail("covariance", "is not a symmetric matrix with a non-negative diagonal");
  p.rms_px = m.Double("rms_px", 0.0);
  return p;
}

CameraIntrinsics ParseCamera(YamlMap m, int version, CameraPrecision* precision) {
  // Schema 1 leaves the precision keys unread: RejectUnknownKeys below names them.
  m.RejectKeysOtherThan({"width_px", "height_px", "pixel_size_um", "principal_distance_px",
                         "principal_distance_mm", "principal_point_px", "distortion", "affinity",
                         "sigma", "covariance", "rms_px"});
  if (version >= 2) {
    const CameraPrecision parsed = ParseCameraPrecision(m);
    if (precision) *precision = parsed;
  }
  CameraIntrinsics c;
  c.width_px = m.Int("width_px", 1, 100000);
  c.height_px = m.Int("height_px", 1, 100000);
  c.pixel_size_um = m.Double("pixel_size_um", 0.0);
  if (c.pixel_size_um < 0.0) m.Fail("pixel_size_um", "must not be negative");
  const bool px = m.Has("principal_distance_px"), mm = m.Has("principal_distance_mm");
  if (px == mm) m.Fail("principal_distance_px", "give exactly one of _px and _mm");
  if (px) {
    c.principal_distance_px = m.PositiveDouble("principal_distance_px");
  } else {
    if (!(c.pixel_size_um > 0.0))
      m.Fail("principal_distance_mm", "needs pixel_size_um to convert to pixels");
    c.principal_distance_px = m.PositiveDouble("principal_distance_mm") * 1000.0 / c.pixel_size_um;
  }
  if (m.Has("principal_point_px")) {
    const auto pp = m.Doubles("principal_point_px", 2);
    c.principal_point_x_px = pp[0];
    c.principal_point_y_px = pp[1];
  } else {
    c.principal_point_x_px = 0.5 * (c.width_px - 1);
    c.principal_point_y_px = 0.5 * (c.height_px - 1);
  }
  if (m.Has("distortion")) {
    YamlMap d = m.Map("distortion");
    c.k1 = d.Double("k1", 0.0);
    c.k2 = d.Double("k2", 0.0);
    c.k3 = d.Double("k3", 0.0);
    c.p1 = d.Double("p1", 0.0);
    c.p2 = d.Double("p2", 0.0);
    d.RejectUnknownKeys();
  }
  if (m.Has("affinity")) {
    YamlMap a = m.Map("affinity");
    c.scale_x = a.Double("scale_x", 0.0);
    c.shear = a.Double("shear", 0.0);
    a.RejectUnknownKeys();
  }
  m.RejectUnknownKeys();
  std::string why;
  if (!c.Check(&why)) throw ConfigError(m.path() + ": " + why);
  return c;
}

StageKinematics ParseStage(YamlMap m) {
  StageKinematics s;
  s.height_above_mark_m = m.Double("height_above_mark_m", 0.0);
  if (s.height_above_mark_m < 0.0) m.Fail("height_above_mark_m", "must not be negative");
  if (m.Has("levelling_deg")) {
    const auto l = m.Doubles("levelling_deg", 2);
    s.levelling_x_deg = l[0];
    s.levelling_y_deg = l[1];
  }
  s.pan_zero_deg = m.Double("pan_zero_deg", 0.0);
  s.tilt_zero_deg = m.Double("tilt_zero_deg", 0.0);
  s.tilt_axis_offset_m = m.Vector3("tilt_axis_offset_m", Eigen::Vector3d::Zero());
  s.tilt_axis_skew_deg = m.Double("tilt_axis_skew_deg", 0.0);
  s.rig_offset_m = m.Vector3("rig_offset_m", Eigen::Vector3d::Zero());
  s.rig_rotation_opk_deg = m.Vector3("rig_rotation_opk_deg", Eigen::Vector3d::Zero());
  m.RejectUnknownKeys();
  std::string why;
  if (!s.Check(&why)) throw ConfigError(m.path() + ": " + why);
  return s;
}

int SchemaVersion(YamlMap& root) {
  const int version = root.Int("schema_version", 0, 1000000);
  if (version < 1 || version > kCalibrationSchemaVersion)
    root.Fail("schema_version", "unsupported version " + std::to_string(version) +
                                    " (this build reads 1 to " +
                                    std::to_string(kCalibrationSchemaVersion) + ")");
  return version;
}

// sigma: {baseline_m: .., right_relative_opk_deg: [..]}, covariance: [4 x 4], rms_px.
StereoPrecision ParseStereoPrecision(YamlMap& m, int version) {
  StereoPrecision p;
  if (!m.Has("sigma")) return p;
  p.known = true;
  YamlMap sigma = m.Map("sigma");
  p.baseline_sigma_m = sigma.Double("baseline_m");
  p.relative_sigma_deg = sigma.Vector3("right_relative_opk_deg", Eigen::Vector3d::Zero());
  if (!(p.baseline_sigma_m >= 0.0) || (p.relative_sigma_deg.array() < 0.0).any())
    m.Fail("sigma", "must not be negative");
  sigma.RejectUnknownKeys();
  const std::vector<double> c = m.Doubles("covariance", 16);
  for (int i = 0; i < 16; ++i) p.covariance(i / 4, i % 4) = c[i];
  if (!p.covariance.isApprox(p.covariance.transpose(), 1e-9))
    m.Fail("covariance", "is not a symmetric matrix");
  p.rms_px = m.Double("rms_px", 0.0);
  // Schema 2 leaves it unread: RejectUnknownKeys names it.
  if (version >= 3 && m.Has("joint_covariance")) {
    constexpr int kJoint = 2 * kN + 4;
    const std::vector<double> j = m.Doubles("joint_covariance", kJoint * kJoint);
    p.joint_covariance =
        Eigen::Map<const Eigen::Matrix<double, kJoint, kJoint, Eigen::RowMajor>>(j.data());
    if (!p.joint_covariance.isApprox(p.joint_covariance.transpose(), 1e-9))
      m.Fail("joint_covariance", "is not a symmetric matrix");
  }
  return p;
}

// The joint covariance's diagonal blocks are the three covariances it joins.
void CheckJointCovariance(const Calibration& cal, YamlMap& stereo) {
  const Eigen::MatrixXd& j = cal.stereo_precision.joint_covariance;
  if (j.size() == 0) return;
  const auto same = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return (a - b).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1e-300, b.cwiseAbs().maxCoeff());
  };
  if (!cal.left_precision.known || !cal.right_precision.known ||
      !same(j.block(0, 0, kN, kN), cal.left_precision.covariance) ||
      !same(j.block(kN, kN, kN, kN), cal.right_precision.covariance) ||
      !same(j.block(2 * kN, 2 * kN, 4, 4), cal.stereo_precision.covariance))
    stereo.Fail("joint_covariance",
                "its diagonal blocks are not cameras.left.covariance, cameras.right.covariance "
                "and stereo.covariance");
}

}  // namespace

Calibration ParseCalibration(YamlMap root) {
  const int version = SchemaVersion(root);
  Calibration cal;
  YamlMap cameras = root.Map("cameras");
  cal.rig.left = ParseCamera(cameras.Map("left"), version, &cal.left_precision);
  cal.rig.right = ParseCamera(cameras.Map("right"), version, &cal.right_precision);
  cameras.RejectUnknownKeys();
  YamlMap stereo = root.Map("stereo");
  cal.rig.baseline_m = stereo.PositiveDouble("baseline_m");
  cal.rig.S_from_left = StereoRig::NominalSFromCamera() *
                        RotationFromOpkDeg(stereo.Vector3("left_rotation_opk_deg", {0, 0, 0}));
  cal.rig.left_from_right = RotationFromOpkDeg(stereo.Vector3("right_relative_opk_deg", {0, 0, 0}));
  if (version >= 2) cal.stereo_precision = ParseStereoPrecision(stereo, version);
  CheckJointCovariance(cal, stereo);
  stereo.RejectUnknownKeys();
  if (std::string why; !cal.rig.Check(&why)) throw ConfigError(stereo.path() + ": " + why);
  if (root.Has("stage")) cal.stage = ParseStage(root.Map("stage"));
  root.RejectUnknownKeys();
  return cal;
}

Result<Calibration> LoadCalibrationYaml(const std::string& file) {
  try {
    return ParseCalibration(YamlMap(LoadYamlFile(file), ""));
  } catch (const ConfigError& e) {
    return Error{file + ": " + e.what()};
  }
}

namespace {
void EmitVector(YAML::Emitter& out, const char* key, const Eigen::Vector3d& v) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << v.x() << v.y() << v.z()
      << YAML::EndSeq;
}

void EmitDoubles(YAML::Emitter& out, const char* key, const double* values, int count) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < count; ++i) out << values[i];
  out << YAML::EndSeq;
}

void EmitCameraPrecision(YAML::Emitter& out, const CameraPrecision& p) {
  out << YAML::Key << "sigma" << YAML::Value << YAML::Flow << YAML::BeginMap;
  for (int i = 0; i < kN; ++i)
    out << YAML::Key << CameraIntrinsics::kParameterNames[i] << YAML::Value << p.sigma[i];
  out << YAML::EndMap;
  const Eigen::Matrix<double, kN, kN, Eigen::RowMajor> c = p.covariance;
  EmitDoubles(out, "covariance", c.data(), kN * kN);
  out << YAML::Key << "rms_px" << YAML::Value << p.rms_px;
}

void EmitStereoPrecision(YAML::Emitter& out, const StereoPrecision& p) {
  out << YAML::Key << "sigma" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "baseline_m" << YAML::Value << p.baseline_sigma_m;
  EmitVector(out, "right_relative_opk_deg", p.relative_sigma_deg);
  out << YAML::EndMap;
  const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> c = p.covariance;
  EmitDoubles(out, "covariance", c.data(), 16);
  out << YAML::Key << "rms_px" << YAML::Value << p.rms_px;
  if (p.joint_covariance.size() == 0) return;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> j =
      p.joint_covariance;
  EmitDoubles(out, "joint_covariance", j.data(), static_cast<int>(j.size()));
}

void EmitCamera(YAML::Emitter& out, const char* name, const CameraIntrinsics& c,
                const CameraPrecision& precision) {
  out << YAML::Key << name << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "width_px" << YAML::Value << c.width_px;
  out << YAML::Key << "height_px" << YAML::Value << c.height_px;
  out << YAML::Key << "pixel_size_um" << YAML::Value << c.pixel_size_um;
  out << YAML::Key << "principal_distance_px" << YAML::Value << c.principal_distance_px;
  out << YAML::Key << "principal_point_px" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << c.principal_point_x_px << c.principal_point_y_px << YAML::EndSeq;
  out << YAML::Key << "distortion" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "k1" << YAML::Value << c.k1 << YAML::Key << "k2" << YAML::Value << c.k2;
  out << YAML::Key << "k3" << YAML::Value << c.k3 << YAML::Key << "p1" << YAML::Value << c.p1;
  out << YAML::Key << "p2" << YAML::Value << c.p2 << YAML::EndMap;
  out << YAML::Key << "affinity" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "scale_x" << YAML::Value << c.scale_x;
  out << YAML::Key << "shear" << YAML::Value << c.shear << YAML::EndMap;
  if (precision.known) EmitCameraPrecision(out, precision);
  out << YAML::EndMap;
}
}  // namespace

std::string CalibrationToYaml(const Calibration& cal) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  const int version = cal.stereo_precision.known && cal.stereo_precision.joint_covariance.size() > 0
                          ? kCalibrationSchemaVersion
                          : kCalibrationSchemaWithoutJoint;
  out << YAML::Key << "schema_version" << YAML::Value << version;
  out << YAML::Key << "cameras" << YAML::Value << YAML::BeginMap;
  EmitCamera(out, "left", cal.rig.left, cal.left_precision);
  EmitCamera(out, "right", cal.rig.right, cal.right_precision);
  out << YAML::EndMap;
  out << YAML::Key << "stereo" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "baseline_m" << YAML::Value << cal.rig.baseline_m;
  EmitVector(out, "left_rotation_opk_deg",
             OpkDegFromRotation(StereoRig::NominalSFromCamera().transpose() * cal.rig.S_from_left));
  EmitVector(out, "right_relative_opk_deg", OpkDegFromRotation(cal.rig.left_from_right));
  if (cal.stereo_precision.known) EmitStereoPrecision(out, cal.stereo_precision);
  out << YAML::EndMap;
  const StageKinematics& s = cal.stage;
  out << YAML::Key << "stage" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "height_above_mark_m" << YAML::Value << s.height_above_mark_m;
  out << YAML::Key << "levelling_deg" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << s.levelling_x_deg << s.levelling_y_deg << YAML::EndSeq;
  out << YAML::Key << "pan_zero_deg" << YAML::Value << s.pan_zero_deg;
  out << YAML::Key << "tilt_zero_deg" << YAML::Value << s.tilt_zero_deg;
  EmitVector(out, "tilt_axis_offset_m", s.tilt_axis_offset_m);
  out << YAML::Key << "tilt_axis_skew_deg" << YAML::Value << s.tilt_axis_skew_deg;
  EmitVector(out, "rig_offset_m", s.rig_offset_m);
  EmitVector(out, "rig_rotation_opk_deg", s.rig_rotation_opk_deg);
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

Status SaveCalibrationYaml(const Calibration& calibration, const std::string& file) {
  return WriteFileAtomically(file, CalibrationToYaml(calibration));
}

std::string CameraCalibrationToYaml(const CameraIntrinsics& camera,
                                    const CameraPrecision& precision) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "schema_version" << YAML::Value << kCalibrationSchemaWithoutJoint;
  EmitCamera(out, "camera", camera, precision);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

Result<CameraIntrinsics> LoadCameraCalibrationYaml(const std::string& file,
                                                   CameraPrecision* precision) {
  try {
    YamlMap root(LoadYamlFile(file), "");
    const int version = SchemaVersion(root);
    return ParseCamera(root.Map("camera"), version, precision);
  } catch (const ConfigError& e) {
    return Error{file + ": " + e.what()};
  }
}

}  // namespace ts
