#include "processing/matching/station_matching.h"

#include <chrono>
#include <stdexcept>

#include "processing/matching/triangulation.h"

namespace ts {

MatchedPair MatchPairIntoL(const Calibration& calibration, const Rectification& r,
                           const StereoPairImages& p, const PairMatchOptions& options) {
  MatchedPair out;
  out.index = p.index;
  cv::Mat left, right;
  RectifyPair(r, p.left, p.right, &left, &right);
  const std::vector<StereoMatch> matches =
      MatchRectifiedPair(r, left, right, options, &out.summary);
  AppendPairPoints(r, matches, calibration.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg), p.index,
                   &out.cloud);
  return out;
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
  std::vector<PointCloud> clouds(pairs.size());
  result.pairs.resize(pairs.size());
  // One pair per task: OpenCV runs the calls inside a task serially, so the cores are not
  // oversubscribed.
  cv::parallel_for_(
      cv::Range(0, static_cast<int>(pairs.size())),
      [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) {
          MatchedPair m = MatchPairIntoL(calibration, r, pairs[i], options);
          clouds[i] = std::move(m.cloud);
          result.pairs[i] = m.summary;
        }
      },
      static_cast<double>(pairs.size()));
  for (PointCloud& c : clouds) result.cloud.insert(result.cloud.end(), c.begin(), c.end());
  const auto t2 = std::chrono::steady_clock::now();
  result.rectification_s = std::chrono::duration<double>(t1 - t0).count();
  result.pairs_s = std::chrono::duration<double>(t2 - t1).count();
  return result;
}

}  // namespace ts
