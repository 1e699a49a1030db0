// The stereo calibration adjustment on a simulated board session's corners projected exactly
// through the true (imperfect) rig, with Gaussian noise of a known sigma: no detector between
// truth and adjustment. What is left is the adjustment and the model: the principal distance
// and the baseline within issue 20's targets (0.05 %, 0.2 mm), the principal point and the
// angles within what the boards' geometry determines, and sigmas that are honest over ten seeds
// (RMS of error / sigma in 0.7-1.5).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processing/calibration/camera_calibration.h"
#include "sim/calibration_views.h"
#include "tests/common/calibration_errors.h"

namespace ts::sim {
namespace {

// The corners of one view inside the frame: a board running off the frame gives a partial
// view, as a ChArUco board does.
void AddProjectedView(const CameraIntrinsics& camera, const Eigen::Isometry3d& camera_from_board,
                      const BoardPlacement& p, int placement, double noise_px, std::mt19937_64& rng,
                      TargetViews* views) {
  std::normal_distribution<double> n(0.0, noise_px);
  const CameraModel model(camera);
  TargetView view{p.name, placement, {}, {}};
  for (size_t id = 0; id < views->target.size(); ++id) {
    Eigen::Vector2d pixel;
    if (!model.Project(camera_from_board * views->target[id], &pixel) || !model.InImage(pixel))
      continue;
    view.ids.push_back(static_cast<int>(id));
    view.pixels.push_back(pixel + Eigen::Vector2d(n(rng), n(rng)));
  }
  if (view.ids.size() >= 8) views->views.push_back(std::move(view));
}

// A session as a field team should take it (the default BoardSessionOptions: 40 placements of
// a 16 x 11 board, tilted up to 50 deg, 2-4 m away) with the detector's noise on rendered
// boards (0.03-0.08 px). Measured on seeds 1-10: principal distance within 0.016 %, baseline
// within 0.04 mm, and the principal point within 0.6 px and the angles within 0.013 deg at
// sigmas of 0.2-0.3 px and 0.005 deg: what the boards' geometry determines (the principal
// point is 0.94 correlated with decentring), not a bias.
TEST(ExactBoardCorners, StereoCalibrationIsAccurateWithHonestSigmas) {
  constexpr double kNoisePx = 0.05;
  StereoErrors errors;
  for (int seed = 1; seed <= 10; ++seed) {
    const SimRig rig = MakeSimRig(seed, 1.5);
    const StereoRig& truth = rig.truth.rig;
    const BoardSessionOptions options;
    const std::vector<BoardPlacement> session = PlanBoardSession(rig, seed, options);
    const Eigen::Isometry3d right_from_left = truth.RightFromLeftCamera();
    TargetViews left, right;
    for (auto [v, camera] : {std::pair{&left, &truth.left}, std::pair{&right, &truth.right}}) {
      v->target = ChessboardCorners(options.Board());
      v->width_px = camera->width_px;
      v->height_px = camera->height_px;
    }
    std::mt19937_64 rng(seed);
    for (size_t k = 0; k < session.size(); ++k) {
      if (!session[k].board) continue;
      const int placement = static_cast<int>(k);
      AddProjectedView(truth.left, session[k].left_from_board, session[k], placement, kNoisePx, rng,
                       &left);
      AddProjectedView(truth.right, right_from_left * session[k].left_from_board, session[k],
                       placement, kNoisePx, rng, &right);
    }
    CameraCalibrationOptions calibration;
    calibration.corner_sigma_px = kNoisePx;
    const Result<StereoCalibration> s = CalibrateStereo(left, right, calibration);
    ASSERT_TRUE(s.ok()) << s.error();
    errors.Add(*s, truth);
  }
  const auto& [c_rel, pp, baseline, angles, distortion] = errors;
  std::printf(
      "largest error (RMS error/sigma): c %.4f %% (%.2f), pp %.3f px (%.2f), baseline %.4f mm "
      "(%.2f), angles %.4f deg (%.2f)\n",
      100 * c_rel.MaxAbs(), c_rel.NormalisedRms(), pp.MaxAbs(), pp.NormalisedRms(),
      1e3 * baseline.MaxAbs(), baseline.NormalisedRms(), angles.MaxAbs(), angles.NormalisedRms());
  EXPECT_LT(c_rel.MaxAbs(), 5e-4);
  EXPECT_LT(baseline.MaxAbs(), 2e-4);
  EXPECT_LT(pp.MaxAbs(), 1.0);
  EXPECT_LT(angles.MaxAbs(), 0.02);
  for (const CalibrationErrors* e : {&c_rel, &pp, &baseline, &angles}) {
    EXPECT_GT(e->NormalisedRms(), 0.7);
    EXPECT_LT(e->NormalisedRms(), 1.5);
  }
}

}  // namespace
}  // namespace ts::sim
