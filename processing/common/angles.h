#pragma once
// Directions seen from one point.
#include <algorithm>
#include <cmath>
#include <vector>

namespace ts {

// The largest gap (radians) between directions (atan2 angles) around a point: over pi, they all
// lie within a half-plane through it. 2 pi when there are none.
inline double LargestAngularGap(std::vector<double> angles) {
  if (angles.empty()) return 2.0 * M_PI;
  std::sort(angles.begin(), angles.end());
  double gap = 2.0 * M_PI - (angles.back() - angles.front());
  for (size_t i = 1; i < angles.size(); ++i) gap = std::max(gap, angles[i] - angles[i - 1]);
  return gap;
}

// The angle (degrees, 0-180) between two directions given in degrees, whatever their turns.
inline double AngleBetweenDeg(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

}  // namespace ts
