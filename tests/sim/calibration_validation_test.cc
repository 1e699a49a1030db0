// Split-half validation and the verdict on board sessions of the simulated rig, their corners
// projected exactly through the true cameras with 0.05 px of noise: the halves of a full
// session agree within their sigmas, a session whose boards all stay in the middle needs views
// at the edges, and one where every other placement saw a different right camera (a systematic
// error the model does not know) is overfitted.
#include <gtest/gtest.h>

#include <random>

#include "processing/calibration/calibration_validation.h"
#include "sim/calibration_views.h"

namespace ts::sim {
namespace {

struct Session {
  TargetViews left, right;
};

// Each placement's corners inside both frames; `stretch` scales the right image about its
// principal point in odd placements (as if its focus ring had turned between them).
Session Project(const SimRig& rig, const std::vector<BoardPlacement>& placements,
                const BoardSessionOptions& options, double stretch, uint64_t seed) {
  const StereoRig& truth = rig.truth.rig;
  const Eigen::Isometry3d right_from_left = truth.RightFromLeftCamera();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  Session s;
  for (auto [views, camera] :
       {std::pair{&s.left, &truth.left}, std::pair{&s.right, &truth.right}}) {
    views->target = ChessboardCorners(options.Board());
    views->width_px = camera->width_px;
    views->height_px = camera->height_px;
  }
  for (size_t k = 0; k < placements.size(); ++k)
    for (auto [views, camera] :
         {std::pair{&s.left, &truth.left}, std::pair{&s.right, &truth.right}}) {
      const CameraModel model(*camera);
      const Eigen::Isometry3d pose =
          (camera == &truth.left ? Eigen::Isometry3d::Identity() : right_from_left) *
          placements[k].left_from_board;
      const Eigen::Vector2d pp(camera->principal_point_x_px, camera->principal_point_y_px);
      TargetView view{placements[k].name, static_cast<int>(k), {}, {}};
      for (size_t id = 0; id < views->target.size(); ++id) {
        Eigen::Vector2d pixel;
        if (!model.Project(pose * views->target[id], &pixel) || !model.InImage(pixel)) continue;
        if (k % 2 && camera == &truth.right) pixel = pp + stretch * (pixel - pp);
        view.ids.push_back(static_cast<int>(id));
        view.pixels.push_back(pixel + Eigen::Vector2d(noise(rng), noise(rng)));
      }
      if (view.ids.size() >= 8) views->views.push_back(std::move(view));
    }
  return s;
}

CalibrationValidation Validate(const Session& s) {
  CameraCalibrationOptions options;
  options.corner_sigma_px = 0.05;
  const Result<StereoCalibration> c = CalibrateStereo(s.left, s.right, options);
  EXPECT_TRUE(c.ok()) << c.error();
  if (!c) return {};
  const CalibrationValidation v = ValidateStereo(*c, s.left, s.right, options, {});
  for (const MapValidation& m : v.maps)
    std::printf("  %.0f m: sigma %.3f px max (%.3f median), halves %.3f px, consistency %.2f\n",
                m.distance_m, m.max_sigma_px, m.median_sigma_px, m.max_difference_px,
                m.consistency);
  std::printf("  %s: %s\n", v.verdict.c_str(), v.reason.c_str());
  return v;
}

// A board session as a team takes it: the halves agree within their sigmas, and the map is
// known to about a tenth of a pixel (the corners of the frame, which boards do not reach, set
// it; field_calibration_test.cc: a field session is good).
TEST(CalibrationValidation, TheHalvesOfAFullSessionAgreeWithinTheirSigmas) {
  const SimRig rig = MakeSimRig(1, 1.5);
  BoardSessionOptions options;
  options.placements = 60;
  const std::vector<BoardPlacement> placements = PlanBoardSession(rig, 1, options);
  const CalibrationValidation v = Validate(Project(rig, placements, options, 1.0, 1));
  ASSERT_EQ(v.maps.size(), 2u);
  for (const MapValidation& m : v.maps) {
    EXPECT_TRUE(m.split);
    EXPECT_GT(m.consistency, 0.2);
    EXPECT_LT(m.consistency, 2.0);
    EXPECT_LT(m.max_sigma_px, 0.2);
  }
  EXPECT_NE(v.verdict, "overfitted") << v.reason;
}

TEST(CalibrationValidation, BoardsOnlyInTheMiddleNeedViewsAtTheEdges) {
  const SimRig rig = MakeSimRig(2, 1.5);
  BoardSessionOptions options;
  options.placements = 60;  // a ninth of them at the frame's centre
  options.min_distance_m = options.max_distance_m = 4.0;
  options.columns = 8, options.rows = 6;
  // Boards whose centre stays in the middle third of the frame.
  std::vector<BoardPlacement> middle;
  const CameraModel model(rig.truth.rig.left);
  for (const BoardPlacement& p : PlanBoardSession(rig, 2, options)) {
    Eigen::Vector2d centre;
    model.Project(p.left_from_board * Eigen::Vector3d(0.25, 0.17, 0), &centre);
    if (std::abs(centre.x() / model.intrinsics().width_px - 0.5) < 0.17 &&
        std::abs(centre.y() / model.intrinsics().height_px - 0.5) < 0.17 && p.board)
      middle.push_back(p);
  }
  ASSERT_GE(middle.size(), 6u);
  const CalibrationValidation v = Validate(Project(rig, middle, options, 1.0, 2));
  EXPECT_EQ(v.verdict, "needs views at the edges") << v.reason;
}

TEST(CalibrationValidation, HalvesThatSawDifferentCamerasAreOverfitted) {
  const SimRig rig = MakeSimRig(3, 1.5);
  BoardSessionOptions options;
  options.placements = 40;
  const std::vector<BoardPlacement> placements = PlanBoardSession(rig, 3, options);
  // 1.001: the right camera's principal distance 1.9 px longer in every other placement.
  const CalibrationValidation v = Validate(Project(rig, placements, options, 1.001, 3));
  EXPECT_EQ(v.verdict, "overfitted") << v.reason;
}

}  // namespace
}  // namespace ts::sim
