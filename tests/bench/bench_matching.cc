// Matching and intersection (issue 5), in one table:
//  - simulated stations (flat, hills; 12 full-resolution pairs each, true calibration):
//    disparity error of every match against the renderer's true range at its pixel, points
//    per pair on ground within 50 m, honesty of the range sigma within 30 m, and the wall
//    time of matching + intersection of all 12 pairs (rectification maps included);
//  - the real Middlebury Cones pair (../shared/data/stereo/middlebury_cones), ours (dense
//    mode) and OpenCV's StereoSGBM (64 disparities, block 5) side by side, against the
//    ground-truth disparity (disp2.png / 4, 0 = unknown). Density: matched share of the known
//    pixels; bad: matched pixels off by more than 1 px. (SGBM here: 83.4 % / 7.0 %; the data
//    README's reference says 82.5 % / 6.2 %: a counting convention we have not pinned down.)
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "processing/common/memory.h"
#include "processing/matching/station_matching.h"
#include "sim/sim_station.h"
#include "tests/bench/bench_table.h"
#include "tests/common/sim_pair.h"

namespace {

using namespace ts;

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

// Renders the 12 pairs of a station with the left views' true range images.
std::vector<StereoPairImages> RenderStation(const sim::SimStation& station,
                                            std::vector<cv::Mat>* left_ranges) {
  const std::vector<StagePose> plan = MakeCapturePlan(station.rig.truth, {});
  std::vector<StereoPairImages> pairs(plan.size());
  left_ranges->resize(plan.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(plan.size())), [&](const cv::Range& range) {
    sim::Renderer renderer(station.scene, station.mesh);
    for (int i = range.start; i < range.end; ++i)
      pairs[i] = testing::RenderSimPair(renderer, station, i, plan[i].pan_deg, plan[i].tilt_deg,
                                        &(*left_ranges)[i]);
  });
  return pairs;
}

void SimulatedStation(const std::string& scene, bench::Table* table) {
  sim::SimStationOptions options;
  options.scene = scene;
  options.seed = 6;
  const auto station = *sim::BuildSimStation(options);
  const Calibration& cal = station->rig.truth;
  std::vector<cv::Mat> left_ranges;
  const std::vector<StereoPairImages> pairs = RenderStation(*station, &left_ranges);

  // Timed three times: this VM's wall times vary by 15-30 % between runs of the same code, so
  // the target is judged on the median; the fastest and slowest are reported beside it.
  constexpr int kTimedRuns = 3;
  StationMatchResult result;
  std::vector<double> walls_s;
  for (int run = 0; run < kTimedRuns; ++run) {
    result = MatchStation(cal, pairs, PairMatchOptions{});
    walls_s.push_back(result.rectification_s + result.pairs_s);
  }
  std::sort(walls_s.begin(), walls_s.end());
  const double wall_s = walls_s[kTimedRuns / 2];

  // Each point of the timed cloud back into its pair's rectified left view: the template
  // centre it was matched at, its disparity, and there the true range.
  const Rectification r = Rectify(cal.rig);
  std::vector<cv::Mat> true_range(pairs.size());
  std::vector<Eigen::Isometry3d> rect_from_l(pairs.size());
  for (size_t i = 0; i < pairs.size(); ++i) {
    cv::remap(left_ranges[i], true_range[i], r.left_map_x, r.left_map_y, cv::INTER_LINEAR,
              cv::BORDER_CONSTANT, NAN);
    Eigen::Isometry3d left_from_rect = Eigen::Isometry3d::Identity();
    left_from_rect.linear() = r.left_from_rect;
    rect_from_l[i] =
        (cal.LFromCamera(Side::kLeft, pairs[i].pan_deg, pairs[i].tilt_deg) * left_from_rect)
            .inverse();
  }
  std::vector<double> errors, ratios;
  double ground_50m = 0;
  for (const CloudPoint& p : result.cloud) {
    const Eigen::Vector3d q = rect_from_l[p.pair] * p.position_m;
    const double disparity = r.focal_px * r.baseline_m / q.z();
    const int u =
        static_cast<int>(std::lround(r.principal_point_px.x() + r.focal_px * q.x() / q.z()));
    const int v =
        static_cast<int>(std::lround(r.principal_point_px.y() + r.focal_px * q.y() / q.z()));
    const double true_range_m = true_range[p.pair].at<float>(v, u);
    if (!std::isfinite(true_range_m)) continue;
    const Eigen::Vector3d ray(u - r.principal_point_px.x(), v - r.principal_point_px.y(),
                              r.focal_px);
    const double true_d = r.baseline_m * ray.norm() / true_range_m;
    errors.push_back(std::abs(disparity - true_d));
    const double range_m = q.norm();
    const double sigma_range_m = range_m / disparity * p.sigma_disparity_px;
    const Eigen::Vector3d truth = rect_from_l[p.pair].inverse() * (ray.normalized() * true_range_m);
    const bool ground =
        std::abs(truth.z() - station->scene.TerrainHeight(truth.x(), truth.y())) < 0.2;
    if (ground && truth.head<2>().norm() <= 50.0) ++ground_50m;
    if (true_range_m <= 30.0) ratios.push_back((range_m - true_range_m) / sigma_range_m);
  }
  const double median = Quantile(errors, 0.5), p95 = Quantile(errors, 0.95);
  const double bad = std::count_if(errors.begin(), errors.end(), [](double e) { return e > 1; }) /
                     static_cast<double>(errors.size());
  double sum2 = 0.0;
  for (double q : ratios) sum2 += q * q;
  const double ratio_rms = std::sqrt(sum2 / ratios.size());
  const double per_pair = ground_50m / pairs.size();
  const std::string s = scene + ": ";
  table->Add(
      {s + "matched points per pair", static_cast<double>(errors.size()) / pairs.size(), "", ""});
  table->Add(
      {s + "ground points within 50 m per pair", per_pair, "", ">= 30000", per_pair >= 30000});
  table->Add({s + "median |disparity error|", median, "px", "<= 0.05", median <= 0.05});
  table->Add({s + "p95 |disparity error|", p95, "px", "<= 0.25", p95 <= 0.25});
  table->Add({s + "share off by > 1 px", bad, "", "< 0.005", bad < 0.005});
  table->Add({s + "RMS range error / sigma (<= 30 m)", ratio_rms, "", "0.7 .. 1.5",
              ratio_rms >= 0.7 && ratio_rms <= 1.5});
  table->Add({s + "rectification maps", result.rectification_s, "s", ""});
  table->Add(
      {s + "match + intersect 12 pairs (median of 3)", wall_s, "s", "<= 2.5", wall_s <= 2.5});
  table->Add({s + "  fastest of the 3", walls_s.front(), "s", ""});
  table->Add({s + "  slowest of the 3", walls_s.back(), "s", ""});
  table->Add({s + "points in the merged cloud", static_cast<double>(result.cloud.size()), "", ""});
}

int MiddleburyCones(bench::Table* table) {
  const std::string dir = TS_SHARED_DATA_DIR "/stereo/middlebury_cones/";
  const cv::Mat left = cv::imread(dir + "im2.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat right = cv::imread(dir + "im6.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat truth = cv::imread(dir + "disp2.png", cv::IMREAD_GRAYSCALE);
  if (left.empty() || right.empty() || truth.empty())
    return std::fprintf(stderr, "%s: Middlebury Cones images missing\n", dir.c_str()), 1;
  const int known = cv::countNonZero(truth);

  cv::Mat sgbm_disparity;
  const auto t0 = std::chrono::steady_clock::now();
  // P1, P2 as in OpenCV's stereo_match sample (8 and 32 times block^2).
  cv::StereoSGBM::create(0, 64, 5, 8 * 25, 32 * 25)->compute(left, right, sgbm_disparity);
  const double sgbm_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int sgbm_matched = 0, sgbm_bad = 0;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      const int t = truth.at<uint8_t>(y, x);
      const short d = sgbm_disparity.at<short>(y, x);
      if (t == 0 || d < 0) continue;
      ++sgbm_matched;
      sgbm_bad += std::abs(d / 16.0 - t / 4.0) > 1.0;
    }
  const double sgbm_density = static_cast<double>(sgbm_matched) / known;
  const double sgbm_bad_share = static_cast<double>(sgbm_bad) / sgbm_matched;

  // Ours in dense mode: every pixel, small windows (the scene has 1-2 px wide structures);
  // the images are rectified already, the disparity range is SGBM's.
  PairMatchOptions options;
  options.dense_step_px = 1;
  options.dense_finest_level = 0;
  options.lsm.half_window_px = 4;
  options.lsm.max_sigma_px = 0.5;
  options.min_disparity_px = 0;
  options.max_disparity_px = 63;
  Rectification r;
  r.focal_px = 1.0;
  r.baseline_m = 1.0;
  cv::Mat lf, rf;
  left.convertTo(lf, CV_32F);
  right.convertTo(rf, CV_32F);
  const auto t1 = std::chrono::steady_clock::now();
  const std::vector<StereoMatch> matches = MatchRectifiedPair(r, lf, rf, options);
  const double ours_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  int ours_matched = 0, ours_bad = 0;
  for (const StereoMatch& m : matches) {
    const int t =
        truth.at<uint8_t>(static_cast<int>(m.left_px.y()), static_cast<int>(m.left_px.x()));
    if (t == 0) continue;
    ++ours_matched;
    ours_bad += std::abs(m.disparity_px - t / 4.0) > 1.0;
  }
  const double density = static_cast<double>(ours_matched) / known;
  const double bad_share = ours_matched ? static_cast<double>(ours_bad) / ours_matched : 1.0;
  table->Add({"Cones: SGBM density (of known pixels)", sgbm_density, "", ""});
  table->Add({"Cones: ours density", density, "", ">= 0.5", density >= 0.5});
  table->Add({"Cones: SGBM bad share (> 1 px)", sgbm_bad_share, "", ""});
  table->Add({"Cones: ours bad share", bad_share, "", "< SGBM", bad_share < sgbm_bad_share});
  table->Add({"Cones: SGBM time", sgbm_s, "s", ""});
  table->Add({"Cones: ours time", ours_s, "s", ""});
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ts::RetainFreedMemory();  // as the appliance does (processing/common/memory.h)
  bench::Table table("matching and intersection: simulator truth and Middlebury Cones");
  for (const char* scene : {"flat", "hills"}) SimulatedStation(scene, &table);
  if (MiddleburyCones(&table) != 0) return 1;
  return table.Finish(argc, argv);
}
