#pragma once
// Tests of many values at once: how far out one of them must lie before chance alone is an
// unlikely explanation.
#include <cmath>

namespace ts {

// The two-sided probability that a standard normal lies beyond +-k.
inline double TwoSidedTail(double k) { return std::erfc(k / std::sqrt(2.0)); }

// k for n values: a standard normal exceeds k (two-sided) in any of them with probability at
// most alpha (Bonferroni; conservative where the values are correlated).
inline double FamilyWiseCriticalValue(int n, double alpha) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (n * TwoSidedTail(mid) > alpha ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace ts
