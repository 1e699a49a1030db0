// Matching of a simulated stereo pair against the renderer's true ranges: every match's
// disparity is compared with the disparity of the true surface at that rectified pixel.
#include "processing/matching/pair_matcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "sim/sim_station.h"
#include "tests/common/terrain_march.h"

namespace ts::sim {
namespace {

TEST(PairMatching, DisparitiesAgreeWithTheTrueSurface) {
  SimStationOptions options;
  options.scene = "hills";
  options.seed = 6;
  const auto station = *BuildSimStation(options);
  const Calibration& cal = station->rig.truth;
  const double pan = 60.0, tilt = AutomaticTiltDeg(cal, {});
  Renderer renderer(station->scene, station->mesh);
  FrameRequest request;
  request.pan_deg = pan;
  request.tilt_deg = tilt;
  request.exposure_us = 5000;
  const cv::Mat left = RenderFrame(renderer, *station, request);
  request.side = Side::kRight;
  const cv::Mat right = RenderFrame(renderer, *station, request);

  const Rectification r = Rectify(cal.rig);
  cv::Mat left_rect, right_rect;
  RectifyPair(r, left, right, &left_rect, &right_rect);
  PairMatchSummary summary;
  const std::vector<StereoMatch> matches =
      MatchRectifiedPair(r, left_rect, right_rect, PairMatchOptions{}, &summary);

  // True disparity: where the match's exact ray meets the terrain, as depth in the rectified
  // frame (independent of the renderer: a march along the ray).
  const Eigen::Isometry3d l_from_camera = cal.LFromCamera(Side::kLeft, pan, tilt);
  std::vector<double> errors;
  for (const StereoMatch& m : matches) {
    const Eigen::Vector3d ray_rect(m.left_px.x() - r.principal_point_px.x(),
                                   m.left_px.y() - r.principal_point_px.y(), r.focal_px);
    const Eigen::Vector3d ray_camera = (r.left_from_rect * ray_rect).normalized();
    const double t = testing::MarchToTerrain(station->scene, l_from_camera.translation(),
                                             l_from_camera.linear() * ray_camera);
    if (std::isnan(t)) continue;
    const double depth = (r.left_from_rect.transpose() * (t * ray_camera)).z();
    errors.push_back(std::abs(m.disparity_px - r.focal_px * r.baseline_m / depth));
  }
  ASSERT_GT(errors.size(), 4000u) << summary.interest_points << " points, " << summary.ncc_accepted
                                  << " NCC, " << summary.lsm_accepted << " LSM, "
                                  << summary.consistent << " consistent";
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  const double p95 = errors[errors.size() * 95 / 100];
  const double bad =
      static_cast<double>(errors.end() - std::upper_bound(errors.begin(), errors.end(), 1.0)) /
      errors.size();
  RecordProperty("matches", static_cast<int>(errors.size()));
  std::printf("matches %zu, median %.3f px, p95 %.3f px, > 1 px %.2f %%\n", errors.size(), median,
              p95, 100 * bad);
  // The level of this first matcher (measured: median 0.103, p95 0.341 px, 0.07 % > 1 px),
  // as a guard against regressions. Issue 5's targets (0.05 / 0.25 px, 0.5 %, >= 30 000
  // points per pair) belong to its benchmark and are not reached yet.
  EXPECT_LT(median, 0.13);
  EXPECT_LT(p95, 0.42);
  EXPECT_LT(bad, 0.005);
}

}  // namespace
}  // namespace ts::sim
