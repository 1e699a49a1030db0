#pragma once
// Tie points of a panorama for the rig adjustment (rig_adjustment.h): each pair's stereo points
// (MatchPairIntoL with the calibration to be refined) sought in the left image of every
// neighbouring pose whose view overlaps. A point is predicted there with the calibration,
// its window of the pair's left image warped by the predicted local mapping (the two views are
// turned about the stage's axes, so the mapping is nearly the rotation's), found by normalised
// cross-correlation within search_px of the prediction (the stage may be off by a few tenths of
// a degree), and refined by least-squares matching. Each tie point is then observed in the
// pair's two images (the right one through the held stereo calibration) and the neighbour's.
#include <map>
#include <memory>
#include <vector>

#include "core/options.h"
#include "processing/calibration/rig_adjustment.h"
#include "processing/matching/lsm.h"
#include "processing/matching/station_matching.h"

namespace ts {

struct RigTiePointOptions {
  int max_per_neighbour = 50;  // tie points sought between a pair and one neighbour
  double search_px = 25.0;     // a stage off by 0.5 deg moves a prediction by 16 px
  int half_window_px = 10;
  double min_correlation = 0.8;
  int min_candidates = 30;  // a neighbour's view overlaps when it holds this many of the points
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("max_per_neighbour", self.max_per_neighbour,
      {"tie points sought between a pair and one neighbour", "", 1, 100000});
    v("search_px", self.search_px, {"search about the prediction", "px", 1, 500});
    v("half_window_px", self.half_window_px, {"matching window half width", "px", 3, 50});
    v("min_correlation", self.min_correlation, {"weaker matches are not kept", "", 0, 1});
    v("min_candidates", self.min_candidates,
      {"a neighbour overlaps when its view holds this many of a pair's points", "", 1, 100000});
  }
  bool Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }
};

struct RigTiePair;

// The tie points of a panorama found as its pairs come (the incremental station): a pair's
// points sought in every pair added before it, and theirs in it. Each pair-to-pair search
// depends on those two pairs only, so the tie points are the same, to the bit, however the
// pairs were added. Not thread-safe: one owner at a time.
class RigTieFinder {
 public:
  RigTieFinder(const Calibration& calibration, const RigTiePointOptions& options);
  ~RigTieFinder();
  RigTieFinder(const RigTieFinder&) = delete;
  RigTieFinder& operator=(const RigTieFinder&) = delete;
  // Pairs (their left images) and their points matched with the calibration, in the same
  // order; the searches run in parallel. A pair added again (captured again) is replaced.
  void Add(const std::vector<StereoPairImages>& pairs, const std::vector<MatchedPair>& matched);
  // Added at this read-back.
  bool Has(int index, double pan_deg, double tilt_deg) const;
  // The tie points among the pairs of these indices (all added), posed in this order.
  RigAdjustmentInput Input(const std::vector<int>& order) const;

 private:
  const Calibration calibration_;
  const RigTiePointOptions options_;
  std::map<int, std::shared_ptr<const RigTiePair>> pairs_;    // by pair index
  std::map<std::pair<int, int>, RigAdjustmentInput> blocks_;  // (from, to): poses 0 and 1
};

// All at once. pairs and matched in the same order (MatchPairsIntoL's result for these pairs).
RigAdjustmentInput FindRigTiePoints(const Calibration& calibration,
                                    const std::vector<StereoPairImages>& pairs,
                                    const std::vector<MatchedPair>& matched,
                                    const RigTiePointOptions& options);

}  // namespace ts
