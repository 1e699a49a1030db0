// The cameras refined in the rig adjustment (issue 21, rig_cameras.h), on exact geometry: the
// simulated rig's true cameras off by a draw from the covariance their calibration reports,
// as calibrated cameras are. Held, the stage's sigmas carry the cameras' stated covariance;
// refined, the sigmas describe the errors too, and the cameras come closer to the truth.
#include "processing/calibration/rig_cameras.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processing/calibration/camera_calibration.h"
#include "processing/calibration/rig_adjustment.h"
#include "processing/calibration/rig_control_field.h"
#include "processing/geometry/camera_model.h"
#include "processing/geometry/rotation.h"
#include "sim/sim_rig.h"
#include "tests/common/projected_field_session.h"
#include "tests/common/stage_truth.h"

namespace ts::sim {
namespace {

using testing::IsStageOffset;
using testing::ProjectedFieldSession;
using testing::ProjectFieldSession;
using testing::TruthInTheEstimatesGauge;

// Plausible sigmas of a board calibration: c, xp, yp (px), k1, k2, k3 (held, as a calibration
// leaves an insignificant term), p1, p2, scale_x, shear; the baseline (m) and the relative
// orientation (deg).
constexpr std::array<double, CameraIntrinsics::kNumParameters> kIntrinsicsSigma = {
    0.5, 0.3, 0.3, 2e-4, 5e-4, 0.0, 2e-5, 2e-5, 2e-5, 2e-5};
constexpr std::array<double, kStereoParameterCount> kStereoSigma = {1e-4, 0.003, 0.003, 0.003};

// The truth's cameras off by a draw from the covariance the calibration states (or, `exact`,
// not off, that covariance stated); the design stage (the truth's azimuth datum) to start from.
Calibration CalibratedCameras(const SimRig& rig, uint64_t seed, bool exact = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> draw(0.0, 1.0);
  const auto n = [&](std::mt19937_64& r) { return exact ? 0.0 : draw(r); };
  Calibration c = rig.truth;
  c.stage = rig.nominal.stage;
  c.stage.pan_zero_deg = rig.truth.stage.pan_zero_deg;
  for (Side side : {Side::kLeft, Side::kRight}) {
    CameraIntrinsics& camera = side == Side::kLeft ? c.rig.left : c.rig.right;
    CameraPrecision& precision = side == Side::kLeft ? c.left_precision : c.right_precision;
    IntrinsicsVector v = camera.ToParameters();
    precision.known = true;
    for (int i = 0; i < CameraIntrinsics::kNumParameters; ++i) {
      v[i] += kIntrinsicsSigma[i] * n(rng);
      precision.sigma[i] = kIntrinsicsSigma[i];
      precision.covariance(i, i) = kIntrinsicsSigma[i] * kIntrinsicsSigma[i];
    }
    camera = CameraIntrinsics::FromParameters(v, camera.width_px, camera.height_px,
                                              camera.pixel_size_um);
  }
  StereoVector s = StereoVectorOf(c.rig);
  StereoPrecision& p = c.stereo_precision;
  p.known = true;
  for (int k = 0; k < kStereoParameterCount; ++k) {
    s[k] += kStereoSigma[k] * n(rng);
    p.covariance(k, k) = kStereoSigma[k] * kStereoSigma[k];
  }
  p.baseline_sigma_m = kStereoSigma[0];
  p.relative_sigma_deg = {kStereoSigma[1], kStereoSigma[2], kStereoSigma[3]};
  c.rig.baseline_m = s[0];
  c.rig.left_from_right = RotationFromOpkDeg(Eigen::Vector3d(s[1], s[2], s[3]));
  return c;
}

Result<RigAdjustment> AdjustAtField(const Calibration& start, const ProjectedFieldSession& f,
                                    bool refine_cameras) {
  const Result<RigAdjustmentInput> in = ControlFieldInput(start, f.measured, f.poses);
  if (!in) return Error{in.error()};
  RigAdjustmentOptions options;
  options.refine_cameras = refine_cameras;
  return AdjustRig(*in, options);
}

// Sums of squared (estimate - truth) / sigma.
struct Ratios {
  double squares = 0.0;
  int n = 0;
  void Add(double error, double sigma) {
    squares += (error / sigma) * (error / sigma);
    ++n;
  }
  double Rms() const { return std::sqrt(squares / std::max(1, n)); }
};

// `of_the_data`: against the data's share of each sigma alone.
void AddOffsets(const SimRig& rig, const RigAdjustment& r, Ratios* ratios,
                bool of_the_data = false) {
  const StageVector estimate = StageVectorOf(r.stage);
  const StageVector truth = TruthInTheEstimatesGauge(rig.truth, r);
  for (int i = 0; i < kStageParameterCount; ++i)
    if (IsStageOffset(i) && r.sigma[i] > 0.0)
      ratios->Add(estimate[i] - truth[i], of_the_data ? r.SigmaOfTheData()[i] : r.sigma[i]);
}

// Ten control field sessions, the cameras calibrated (off by their stated covariance). Held,
// the offsets' errors are several of the sigmas the data alone give them, and their sigmas with
// the cameras' covariance carried describe them (RMS of error / sigma within 0.7-1.5); refined,
// the sigmas describe them too, as they do for the refined cameras' own parameters, which come
// closer to the truth than their calibration was.
TEST(RigCameras, HeldOrRefinedAtAControlFieldTheirErrorsEnterTheStagesSigmas) {
  Ratios held, held_data_only, refined, cameras;
  double c_error_before = 0.0, c_error_after = 0.0;
  for (int seed = 21; seed <= 30; ++seed) {
    const SimRig rig = MakeSimRig(seed, 1.5);
    const ProjectedFieldSession f = ProjectFieldSession(rig, seed);
    const Calibration start = CalibratedCameras(rig, seed);
    const Result<RigAdjustment> h = AdjustAtField(start, f, false);
    ASSERT_TRUE(h.ok()) << h.error();
    EXPECT_FALSE(h->cameras.refined);
    EXPECT_EQ(h->cameras.rig.left.principal_distance_px, start.rig.left.principal_distance_px);
    AddOffsets(rig, *h, &held);
    AddOffsets(rig, *h, &held_data_only, true);
    const Result<RigAdjustment> r = AdjustAtField(start, f, true);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_TRUE(r->cameras.refined);
    AddOffsets(rig, *r, &refined);
    const RigCameraVector truth = RigCameraVectorOf(rig.truth.rig);
    const RigCameraVector before = RigCameraVectorOf(start.rig);
    const RigCameraVector after = RigCameraVectorOf(r->cameras.rig);
    const RigCameraVector sigma = RigCameraSigmas(r->cameras);
    for (int i = 0; i < kRigCameraParameterCount; ++i) {
      if (sigma[i] == 0.0) {
        EXPECT_EQ(after[i], before[i]) << RigCameraParameterName(i) << ": held by its calibration";
        continue;
      }
      cameras.Add(after[i] - truth[i], sigma[i]);
    }
    for (int side : {0, CameraIntrinsics::kNumParameters}) {
      c_error_before += std::pow(before[side] - truth[side], 2);
      c_error_after += std::pow(after[side] - truth[side], 2);
    }
  }
  std::printf(
      "offsets: RMS error/sigma %.2f held (%.2f of the data's alone), %.2f refined (%d "
      "estimates); cameras %.2f\n",
      held.Rms(), held_data_only.Rms(), refined.Rms(), refined.n, cameras.Rms());
  std::printf("c: RMS error %.3f px calibrated, %.3f px refined\n", std::sqrt(c_error_before / 20),
              std::sqrt(c_error_after / 20));
  EXPECT_GT(held_data_only.Rms(), 1.5);
  EXPECT_GE(held.n, 40);
  EXPECT_GT(held.Rms(), 0.7);
  EXPECT_LT(held.Rms(), 1.5);
  EXPECT_GE(refined.n, 40);
  EXPECT_GT(refined.Rms(), 0.7);
  EXPECT_LT(refined.Rms(), 1.5);
  EXPECT_GT(cameras.Rms(), 0.7);
  EXPECT_LT(cameras.Rms(), 1.5);
  EXPECT_LT(c_error_after, c_error_before);
}

// More unknowns, each with a finite prior, can only take information away from the stage: every
// stage parameter's sigma with the cameras refined is at least the data's share of it with them
// held, in the images' a priori scale (each run estimates its own images' sigma, and held
// cameras that are off widen the targets' residuals). The offsets, which a camera's principal
// distance and point move, widen most. And the data can only add to what the calibration knew
// of the cameras: refined, no sigma is wider than held with the calibration's covariance
// carried (Woodbury: the cameras' prior covariance against that prior with the data's
// information added). That holds at one weighing of the images: cameras that are off weigh
// the held run's images lighter, so this test's cameras are exact, their covariance stated.
TEST(RigCameras, RefinedTheStagesSigmasLieBetweenTheDatasAndTheCarriedCameras) {
  const SimRig rig = MakeSimRig(31, 1.5);
  const ProjectedFieldSession f = ProjectFieldSession(rig, 31);
  const Calibration start = CalibratedCameras(rig, 31, true);
  const Result<RigAdjustment> h = AdjustAtField(start, f, false);
  const Result<RigAdjustment> r = AdjustAtField(start, f, true);
  ASSERT_TRUE(h.ok()) << h.error();
  ASSERT_TRUE(r.ok()) << r.error();
  // The sigmas are scaled by each run's own variance component of the images.
  const double scale = r->control[0].image_sigma_px / h->control[0].image_sigma_px;
  // Neither bound is idle: an offset widens when the cameras are refined, and the data narrow
  // an offset well inside what the calibration's covariance alone leaves it.
  double widest = 0.0, most_refined = 1.0;
  for (int i = 0; i < kStageParameterCount; ++i) {
    if (h->sigma[i] == 0.0 || r->sigma[i] == 0.0) continue;
    const double data = scale * h->SigmaOfTheData()[i], carried = h->sigma_from_held_cameras[i];
    const double widened = r->sigma[i] / data;
    std::printf(
        "%-22s sigma %.3g held (%.3g the data's, %.3g the cameras'), %.3g refined: x %.2f "
        "a priori\n",
        kStageParameterNames[i], h->sigma[i], h->SigmaOfTheData()[i], carried, r->sigma[i],
        widened);
    EXPECT_GE(widened, 0.999) << kStageParameterNames[i];
    EXPECT_LE(r->sigma[i], 1.001 * std::hypot(data, carried)) << kStageParameterNames[i];
    if (!IsStageOffset(i)) continue;
    widest = std::max(widest, widened);
    most_refined = std::min(most_refined, r->sigma[i] / std::hypot(data, carried));
  }
  EXPECT_GT(widest, 1.2);
  EXPECT_LT(most_refined, 0.5);
}

// The convergence of the pair at the frames' centres: in the left camera's frame, the angles
// (deg, about its y and x axes) between the left camera's ray and the right camera's ray
// through their centre pixels. The disparity of every match, and so every range, rests on it.
Eigen::Vector2d CentreConvergenceDeg(const StereoRig& rig) {
  const auto centre_ray = [](const CameraIntrinsics& c) {
    return CameraModel(c).RayFromPixel({0.5 * c.width_px, 0.5 * c.height_px}).normalized();
  };
  const Eigen::Vector3d l = centre_ray(rig.left), r = rig.left_from_right * centre_ray(rig.right);
  return {DegFromRad(std::atan2(r.x(), r.z()) - std::atan2(l.x(), l.z())),
          DegFromRad(std::atan2(r.y(), r.z()) - std::atan2(l.y(), l.z()))};
}

// Its sigma from a covariance of the cameras' list (rig_cameras.h), by numeric derivatives.
Eigen::Vector2d CentreConvergenceSigmaDeg(const StereoRig& rig, const Eigen::MatrixXd& covariance) {
  const RigCameraUnknowns at(rig);
  const RigCameraVector v = RigCameraVectorOf(rig);
  Eigen::MatrixXd jacobian(2, kRigCameraParameterCount);
  for (int i = 0; i < kRigCameraParameterCount; ++i) {
    const double h = 1e-6 * std::max(1e-3, std::abs(v[i]));
    std::array<RigCameraUnknowns, 2> moved{at, at};
    for (int k : {0, 1}) {
      RigCameraVector w = v;
      w[i] += k == 0 ? h : -h;
      std::copy(w.begin(), w.begin() + CameraIntrinsics::kNumParameters,
                moved[k].intrinsics[0].begin());
      std::copy(w.begin() + CameraIntrinsics::kNumParameters,
                w.begin() + 2 * CameraIntrinsics::kNumParameters, moved[k].intrinsics[1].begin());
      std::copy(w.begin() + 2 * CameraIntrinsics::kNumParameters, w.end(), moved[k].stereo.begin());
    }
    jacobian.col(i) =
        (CentreConvergenceDeg(moved[0].Rig(rig)) - CentreConvergenceDeg(moved[1].Rig(rig))) /
        (2 * h);
  }
  return (jacobian * covariance * jacobian.transpose()).diagonal().cwiseSqrt();
}

// Calibrate stereo keeps the covariance of the cameras and the pair together (stereo.
// joint_covariance), as its one adjustment found them: a principal point and the pair's angles
// turn the rays almost alike, so the data know their combination far better than each. Ten
// projected control field sessions calibrated from the design cameras: the error of the
// pair's convergence at the frames' centres, against its sigma from the joint covariance,
// has an RMS within 0.7-1.5; from the three blocks alone (the cameras and the pair taken as
// uncorrelated) the sigma is several times too wide. Held in the rig adjustment or drawn for
// a DEM, the blocks alone allow camera errors no calibration of these images gives.
TEST(RigCameras, TheJointCovarianceDescribesThePairsConvergence) {
  Ratios joint, blocks;
  for (int seed = 41; seed <= 50; ++seed) {
    const SimRig rig = MakeSimRig(seed, 1.5);
    const ProjectedFieldSession f = ProjectFieldSession(rig, seed);
    const Result<StereoCalibration> s = CalibrateStereo(
        f.measured[0], f.measured[1], {}, &rig.nominal.rig.left, &rig.nominal.rig.right);
    ASSERT_TRUE(s.ok()) << s.error();
    const Calibration c = CalibrationOf(*s, rig.nominal);
    ASSERT_EQ(c.stereo_precision.joint_covariance.rows(), kRigCameraParameterCount);
    Calibration apart = c;
    apart.stereo_precision.joint_covariance.resize(0, 0);
    const Eigen::Vector2d error = CentreConvergenceDeg(c.rig) - CentreConvergenceDeg(rig.truth.rig);
    const Eigen::Vector2d with_joint = CentreConvergenceSigmaDeg(c.rig, RigCameraCovariance(c));
    const Eigen::Vector2d apart_sigma =
        CentreConvergenceSigmaDeg(c.rig, RigCameraCovariance(apart));
    for (int k : {0, 1}) {
      joint.Add(error[k], with_joint[k]);
      blocks.Add(error[k], apart_sigma[k]);
    }
  }
  std::printf("convergence: RMS error/sigma %.2f with the joint covariance, %.2f with its blocks\n",
              joint.Rms(), blocks.Rms());
  EXPECT_GT(joint.Rms(), 0.7);
  EXPECT_LT(joint.Rms(), 1.5);
  EXPECT_LT(blocks.Rms(), 0.5);
}

// Cameras with design values carry no precision to weigh them by: refining them is refused,
// naming the calibration's field that is missing.
TEST(RigCameras, CamerasWithoutAPrecisionAreNotRefined) {
  const SimRig rig = MakeSimRig(32, 1.5);
  const ProjectedFieldSession f = ProjectFieldSession(rig, 32);
  Calibration start = CalibratedCameras(rig, 32);
  start.right_precision = {};
  const Result<RigAdjustment> r = AdjustAtField(start, f, true);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("cameras.right: no precision"), std::string::npos) << r.error();
  start = CalibratedCameras(rig, 32);
  // The angles correlated beyond what their variances allow.
  start.stereo_precision.covariance(1, 2) = start.stereo_precision.covariance(2, 1) = 1e-3;
  const Status s = CheckCamerasRefinable(start);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("stereo.covariance: not positive definite"), std::string::npos)
      << s.error();
}

}  // namespace
}  // namespace ts::sim
