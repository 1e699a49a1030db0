#include "processing/matching/station_matching.h"

#include <chrono>
#include <stdexcept>

#include "processing/matching/triangulation.h"

namespace ts {

MatchedPair MatchPairIntoL(const Calibration& calibration, const Rectification& r,
                           const StereoPairImages& p, const PairMatchOptions& options) {
  MatchedPair out;
  out.index = p.index;
  out.pan_deg = p.pan_deg;
  out.tilt_deg = p.tilt_deg;
  cv::Mat left, right;
  RectifyPair(r, p.left, p.right, &left, &right);
  const std::vector<StereoMatch> matches =
      MatchRectifiedPair(r, left, right, options, &out.summary);
  AppendPairPoints(r, matches, calibration.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg), p.index,
                   &out.cloud);
  return out;
}

std::vector<MatchedPair> MatchPairsIntoL(const Calibration& calibration, const Rectification& r,
                                         const std::vector<StereoPairImages>& pairs,
                                         const PairMatchOptions& options,
                                         const std::function<bool()>& should_stop,
                                         const std::function<void()>& pair_done) {
  std::vector<MatchedPair> matched(pairs.size(), MatchedPair{-1, 0.0, 0.0, {}, {}});
  cv::parallel_for_(
      cv::Range(0, static_cast<int>(pairs.size())),
      [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) {
          if (should_stop && should_stop()) return;
          matched[i] = MatchPairIntoL(calibration, r, pairs[i], options);
          if (pair_done) pair_done();
        }
      },
      static_cast<double>(pairs.size()));
  return matched;
}

StationMatchResult MatchStation(const Calibration& calibration,
                                const std::vector<StereoPairImages>& pairs,
                                const PairMatchOptions& options) {
  std::string why;
  if (!options.Check(&why)) throw std::invalid_argument("pair matching: " + why);
  StationMatchResult result;
  const auto t0 = std::chrono::steady_clock::now();
  const Rectification r = Rectify(calibration.rig);
  const auto t1 = std::chrono::steady_clock::now();
  for (MatchedPair& m : MatchPairsIntoL(calibration, r, pairs, options)) {
    result.cloud.insert(result.cloud.end(), m.cloud.begin(), m.cloud.end());
    result.pairs.push_back(m.summary);
  }
  const auto t2 = std::chrono::steady_clock::now();
  result.rectification_s = std::chrono::duration<double>(t1 - t0).count();
  result.pairs_s = std::chrono::duration<double>(t2 - t1).count();
  return result;
}

}  // namespace ts
