#include "processing/dem/shared_noise.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ts {
namespace {

PointMatch At(int pair, float x, float y, float half_x = 10, float half_y = 10) {
  return {pair, {{x, y}, {half_x, half_y}}};
}

// Two boxes of white noise correlate by their common area over the geometric mean of their
// areas; 21 x 21 windows (half 10).
TEST(SharedNoise, OneWindowIsOneError) {
  EXPECT_DOUBLE_EQ(SharedNoiseCorrelation(At(3, 100, 50), At(3, 100, 50)), 1.0);
}

TEST(SharedNoise, WindowsHalfOverAlongOneAxisShareHalf) {
  EXPECT_NEAR(SharedNoiseCorrelation(At(3, 100, 50), At(3, 110.5, 50)), 0.5, 1e-6);
  EXPECT_NEAR(SharedNoiseCorrelation(At(3, 100, 50), At(3, 100, 39.5)), 0.5, 1e-6);
  // Half over along both: a quarter of the area.
  EXPECT_NEAR(SharedNoiseCorrelation(At(3, 100, 50), At(3, 110.5, 60.5)), 0.25, 1e-6);
}

TEST(SharedNoise, WindowsApartOrOfOtherPairsShareNothing) {
  EXPECT_EQ(SharedNoiseCorrelation(At(3, 100, 50), At(3, 121, 50)), 0.0);
  EXPECT_EQ(SharedNoiseCorrelation(At(3, 100, 50), At(4, 100, 50)), 0.0);
  EXPECT_EQ(SharedNoiseCorrelation(At(-1, 100, 50), At(-1, 100, 50)), 0.0);
  EXPECT_EQ(SharedNoiseCorrelation(At(3, 100, 50, 0, 0), At(3, 100, 50, 0, 0)), 0.0);
}

// An 11 x 11 window inside a 21 x 21 one: 121 common pixels over sqrt(121 x 441).
TEST(SharedNoise, ASmallWindowInsideALargeOne) {
  EXPECT_NEAR(SharedNoiseCorrelation(At(3, 100, 50, 5, 5), At(3, 102, 49)), 121.0 / 231.0, 1e-6);
}

}  // namespace
}  // namespace ts
