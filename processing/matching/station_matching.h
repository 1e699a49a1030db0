#pragma once
// Matching and intersection of every pair of a station: one rectification for the
// calibration, the pairs matched in parallel (one pair per core), each pair's points taken
// into L with the encoder read-back of its pose, and merged into one cloud in pair order.
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "processing/cloud/point_cloud.h"
#include "processing/geometry/calibration.h"
#include "processing/matching/pair_matcher.h"

namespace ts {

struct StereoPairImages {
  int index = 0;         // pair index in the capture plan
  double pan_deg = 0.0;  // encoder read-back
  double tilt_deg = 0.0;
  cv::Mat left, right;  // as captured (any single-channel type)
};

struct StationMatchResult {
  PointCloud cloud;
  std::vector<PairMatchSummary> pairs;  // in the order given
  double rectification_s = 0.0;         // building the maps
  double pairs_s = 0.0;                 // rectifying, matching and intersecting all pairs
};

// One pair's points: rectified with r (Rectify(calibration.rig)), matched, intersected and
// taken into L with the pair's read-back. The same for a pair alone as inside MatchStation.
struct MatchedPair {
  int index = 0;
  double pan_deg = 0.0, tilt_deg = 0.0;  // the read-back it was taken into L with
  PointCloud cloud;
  PairMatchSummary summary;
};
MatchedPair MatchPairIntoL(const Calibration& calibration, const Rectification& r,
                           const StereoPairImages& pair, const PairMatchOptions& options);

// Every pair through MatchPairIntoL, one pair per task (OpenCV runs the calls inside a task
// serially, so the cores are not oversubscribed), in the order given. Once should_stop()
// says so, pairs not yet started are left out (their MatchedPair is empty, index -1);
// pair_done() is called from the task that finished a pair.
std::vector<MatchedPair> MatchPairsIntoL(const Calibration& calibration, const Rectification& r,
                                         const std::vector<StereoPairImages>& pairs,
                                         const PairMatchOptions& options,
                                         const std::function<bool()>& should_stop = {},
                                         const std::function<void()>& pair_done = {});

StationMatchResult MatchStation(const Calibration& calibration,
                                const std::vector<StereoPairImages>& pairs,
                                const PairMatchOptions& options);

}  // namespace ts
