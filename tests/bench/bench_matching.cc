// Matching on the real Middlebury Cones pair (../shared/data/stereo/middlebury_cones), ours
// and OpenCV's StereoSGBM (64 disparities, block 5) side by side, against the ground-truth
// disparity (disp2.png / 4, 0 = unknown). Density: matched share of the known pixels; bad:
// matched pixels off by more than 1 px. Issue 5's target: ours below SGBM's bad share at
// >= 50 % density. (SGBM here: 83.4 % density, 7.0 % bad; the data README's reference says
// 82.5 % and 6.2 %: a counting convention we have not pinned down.)
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "processing/matching/pair_matcher.h"
#include "tests/bench/bench_table.h"

int main(int argc, char** argv) {
  using namespace ts;
  const std::string dir = TS_SHARED_DATA_DIR "/stereo/middlebury_cones/";
  const cv::Mat left = cv::imread(dir + "im2.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat right = cv::imread(dir + "im6.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat truth = cv::imread(dir + "disp2.png", cv::IMREAD_GRAYSCALE);
  if (left.empty() || right.empty() || truth.empty())
    return std::fprintf(stderr, "%s: Middlebury Cones images missing\n", dir.c_str()), 1;
  int known = cv::countNonZero(truth);
  bench::Table table("matching on Middlebury Cones (450x375), ours vs StereoSGBM");

  // OpenCV StereoSGBM, the settings of the data's reference (64 disparities, block 5).
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
  table.Add({"SGBM: density (of known pixels)", sgbm_density, "", ""});
  table.Add({"SGBM: bad share (> 1 px)", sgbm_bad_share, "", ""});
  table.Add({"SGBM: time", sgbm_s, "s", ""});

  // Ours: the images are rectified already; the disparity range is SGBM's.
  PairMatchOptions options;
  options.min_disparity_px = 0;
  options.max_disparity_px = 63;
  options.interest.cell_px = 4;
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
  table.Add({"ours: density (of known pixels)", density, "", ">= 0.5", density >= 0.5});
  table.Add({"ours: bad share (> 1 px)", bad_share, "", "< SGBM", bad_share < sgbm_bad_share});
  table.Add({"ours: time", ours_s, "s", ""});
  return table.Finish(argc, argv);
}
