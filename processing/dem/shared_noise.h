#pragma once
// Matching noise that points share. Each point's height comes from a least-squares window;
// points of one pair whose windows overlap were fitted to partly the same pixels, and their
// errors correlate: kriging's std, the thinning of dense points and the variogram's noise all
// ask how much.
#include "processing/cloud/point_cloud.h"

namespace ts {

// The match a point came from: the pair and its window in the pair's rectified left image.
struct PointMatch {
  int pair = -1;  // none: its error shares nothing with another's
  MatchWindow window;
};

// The correlation of two points' errors: the share of image noise their windows have in
// common. Each window's estimate is a weighted mean over its pixels; two boxes of white noise
// correlate by their overlap over the geometric mean of their areas. Points of different
// pairs were matched in different images: none. Far out a window's ground runs a metre or more
// along the ray, and the errors of one pair's points that near are one error (on the
// simulated slope at 30-45 m: 0.67 within 0.25 m, 0.38 at 0.5-1 m along the ray, against 0.05
// between pairs).
double SharedNoiseCorrelation(const PointMatch& a, const PointMatch& b);

// The covariance of two points' errors of the given variances: their correlation times both
// standard deviations.
double SharedNoiseCovariance(const PointMatch& a, double variance_a, const PointMatch& b,
                             double variance_b);

}  // namespace ts
