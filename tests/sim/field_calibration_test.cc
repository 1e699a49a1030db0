// Calibration at the simulated control field: circular targets rendered exactly through the
// true (imperfect) cameras, each found near its prediction and measured by centroid and
// least-squares matching, then the rig adjusted with the surveyed points free within their
// sigma.
#include <gtest/gtest.h>

#include <random>

#include "processing/calibration/calibration_validation.h"
#include "processing/calibration/circular_target.h"
#include "processing/calibration/field_calibration.h"
#include "sim/calibration_field.h"
#include "sim/sensor.h"
#include "tests/common/calibration_errors.h"
#include "tests/common/field_session.h"

namespace ts::sim {
namespace {

TEST(CircularTargets, AreMeasuredWithinATenthOfAPixelWithHonestSigmas) {
  const SimRig rig = MakeSimRig(1, 1.5);
  const FieldSession s = PlanFieldSession(rig, 1, {});
  const CameraModel model(rig.truth.rig.left);
  const Eigen::Isometry3d station_from_field = s.field_from_station.inverse();
  std::vector<double> errors, normalised;
  int predicted = 0;
  for (int k : {0, 7}) {
    const cv::Mat image = AsFloatImage(ExposeFieldView(rig, s, Side::kLeft, k, 1, {}));
    const Eigen::Isometry3d camera_from_field =
        rig.truth.LFromCamera(Side::kLeft, s.poses[k].pan_deg, s.poses[k].tilt_deg).inverse() *
        station_from_field;
    for (const FieldTarget& t : s.truth.targets) {
      const Eigen::Vector3d p = camera_from_field * t.position_m;
      Eigen::Vector2d truth;
      if (p.z() <= 0 || !model.Project(p, &truth) || truth.x() < 20 || truth.y() < 20 ||
          truth.x() > model.intrinsics().width_px - 20 ||
          truth.y() > model.intrinsics().height_px - 20)
        continue;
      ++predicted;
      const double radius = 0.5 * t.diameter_m * model.intrinsics().principal_distance_px / p.z();
      // Predicted 6 px off, as a design camera would.
      const TargetMeasurement m =
          MeasureCircularTarget(image, truth + Eigen::Vector2d(6, -4), radius, 10.0);
      if (!m.ok) {
        ADD_FAILURE() << "target " << t.id << " at " << truth.transpose() << ": " << m.why;
        continue;
      }
      const Eigen::Vector2d e = m.pixel - truth;
      errors.push_back(e.norm());
      normalised.push_back(e.cwiseAbs().maxCoeff() / m.sigma_px);
    }
  }
  ASSERT_GT(predicted, 80);
  double sum = 0.0;
  for (double e : errors) sum += e * e;
  const double rms = std::sqrt(sum / errors.size());
  std::sort(errors.begin(), errors.end());
  std::sort(normalised.begin(), normalised.end());
  EXPECT_LT(rms, 0.1);
  EXPECT_LT(errors.back(), 0.3);
  // The matching's sigma: the median error near it (not ten times smaller or larger).
  const double median = normalised[normalised.size() / 2];
  EXPECT_GT(median, 0.3);
  EXPECT_LT(median, 3.0);
  std::printf("%zu targets: RMS %.3f px, largest %.3f px, median |error|/sigma %.2f\n",
              errors.size(), rms, errors.back(), median);
}

// Issue 20's targets at the field, from the rendered images: principal distance within
// 0.05 %, principal point within 0.3 px, distortion within 0.1 px everywhere in the frame,
// baseline within 0.2 mm, angles within 0.005 deg (bench_calibration: the same over ten seeds).
TEST(FieldCalibration, RecoversTheTrueRigFromRenderedImages) {
  const int seed = 2;
  const SimRig rig = MakeSimRig(seed, 1.5);
  const FieldSession s = PlanFieldSession(rig, seed, {});
  FieldReport report;
  const Result<StereoCalibration> c =
      CalibrateStereoAtField(s.surveyed, SimulatedFieldViews(rig, s, seed), {}, {}, &report);
  ASSERT_TRUE(c.ok()) << c.error();
  StereoErrors errors;
  errors.Add(*c, rig.truth.rig);
  EXPECT_GT(report.targets_found, 0.9 * s.truth.targets.size());
  EXPECT_LT(c->rejected, 0.005 * c->observations) << "occluded targets are not measured";
  EXPECT_LT(c->rms_px, 0.05);
  EXPECT_LT(errors.c_rel.MaxAbs(), 5e-4);
  EXPECT_LT(errors.pp.MaxAbs(), 0.3);
  EXPECT_LT(errors.distortion_px, 0.1);
  EXPECT_LT(errors.baseline.MaxAbs(), 2e-4);
  EXPECT_LT(errors.angles.MaxAbs(), 0.005);
  // Targets in every part of both frames: the stereo map is known within a tenth of a pixel.
  const CalibrationValidation v = ValidateStereo(*c, report.views[0], report.views[1], {}, {});
  EXPECT_EQ(v.verdict, "good") << v.reason;
}

// A target knocked 30 mm upward since the survey (a blunder across the line of sight, which the
// images see): named in the report as moved by the adjustment, and the cameras still right.
TEST(FieldCalibration, ADisturbedTargetIsNamed) {
  const int seed = 3;
  const SimRig rig = MakeSimRig(seed, 1.5);
  FieldSessionOptions options;
  options.poses.pans = 5;
  options.poses.pan_step_deg = 15.0;
  options.poses.tilts = 3;
  options.poses.tilt_step_deg = 8.0;
  FieldSession s = PlanFieldSession(rig, seed, options);
  s.surveyed.targets[40].position_m.z() += 0.03;  // the images see the true place
  FieldReport report;
  const Result<StereoCalibration> c = CalibrateStereoAtField(
      s.surveyed, SimulatedFieldViews(rig, s, seed, options), {}, {}, &report);
  ASSERT_TRUE(c.ok()) << c.error();
  std::string warnings;
  for (const std::string& w : report.warnings) warnings += w + "\n";
  const std::string id = std::to_string(s.surveyed.targets[40].id);
  EXPECT_NE(warnings.find("moved by the adjustment"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find(id), std::string::npos) << warnings;
  StereoErrors errors;
  errors.Add(*c, rig.truth.rig);
  EXPECT_LT(errors.c_rel.MaxAbs(), 5e-4);
  EXPECT_LT(errors.baseline.MaxAbs(), 2e-4);
}

// The adjustment at the field on exact projections with 0.02 px noise and the survey's 1 mm:
// over ten seeds the sigmas describe the errors (RMS of error / sigma in 0.7-1.5) with the
// surveyed points free within their sigma and the images' sigma estimated as a variance
// component. Held as given, the noisy points would make the sigmas several times too small.
TEST(ExactFieldTargets, StereoAdjustmentHasHonestSigmas) {
  constexpr double kNoisePx = 0.02;
  StereoErrors errors;
  for (int seed = 1; seed <= 10; ++seed) {
    const SimRig rig = MakeSimRig(seed, 1.5);
    const FieldSession s = PlanFieldSession(rig, seed, {});
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, kNoisePx);
    const Eigen::Vector3d centre = s.surveyed.targets[0].position_m;
    std::vector<TargetViews> views(2);
    for (int c = 0; c < 2; ++c) {
      const Side side = c == 0 ? Side::kLeft : Side::kRight;
      const CameraIntrinsics& camera = c == 0 ? rig.truth.rig.left : rig.truth.rig.right;
      const CameraModel model(camera);
      views[c].width_px = camera.width_px;
      views[c].height_px = camera.height_px;
      views[c].pixel_sigma_px = kNoisePx;
      for (const FieldTarget& t : s.surveyed.targets) {
        views[c].target.push_back(t.position_m - centre);
        views[c].target_sigma.push_back(t.sigma_m);
      }
      for (size_t k = 0; k < s.poses.size(); ++k) {
        const Eigen::Isometry3d camera_from_field =
            rig.truth.LFromCamera(side, s.poses[k].pan_deg, s.poses[k].tilt_deg).inverse() *
            s.field_from_station.inverse();
        TargetView view{std::to_string(k), static_cast<int>(k), {}, {}};
        for (size_t i = 0; i < s.truth.targets.size(); ++i) {
          Eigen::Vector2d pixel;
          const Eigen::Vector3d p = camera_from_field * s.truth.targets[i].position_m;
          if (p.z() <= 0 || !model.Project(p, &pixel) || !model.InImage(pixel)) continue;
          view.ids.push_back(static_cast<int>(i));
          view.pixels.push_back(pixel + Eigen::Vector2d(noise(rng), noise(rng)));
        }
        views[c].views.push_back(std::move(view));
      }
    }
    const Result<StereoCalibration> c =
        CalibrateStereo(views[0], views[1], {}, &rig.nominal.rig.left, &rig.nominal.rig.right);
    ASSERT_TRUE(c.ok()) << seed << ": " << c.error();
    errors.Add(*c, rig.truth.rig);
  }
  const auto& [c_rel, pp, baseline, angles, distortion] = errors;
  std::printf(
      "largest error (RMS error/sigma): c %.4f %% (%.2f), pp %.3f px (%.2f), baseline %.4f mm "
      "(%.2f), angles %.4f deg (%.2f), distortion %.3f px\n",
      100 * c_rel.MaxAbs(), c_rel.NormalisedRms(), pp.MaxAbs(), pp.NormalisedRms(),
      1e3 * baseline.MaxAbs(), baseline.NormalisedRms(), angles.MaxAbs(), angles.NormalisedRms(),
      distortion);
  for (const CalibrationErrors* e : {&c_rel, &pp, &baseline}) {
    EXPECT_GT(e->NormalisedRms(), 0.7);
    EXPECT_LT(e->NormalisedRms(), 1.5);
  }
}

}  // namespace
}  // namespace ts::sim
