#include "processing/gravity/prism.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ts {
namespace {

constexpr double kG = kGravitationalConstant;

// A slab 10 m thick under the point: a square prism growing to 1e9 m sides converges to the
// Bouguer slab 2 pi G rho h, monotonically from below.
TEST(Prism, ConvergesToTheBouguerSlab) {
  const double h = 10.0, slab = 2 * M_PI * kG * kStandardDensityKgM3 * h;
  double previous = 0.0;
  for (double a = 10.0; a <= 1e9; a *= 10.0) {
    const double g = PrismDownwardAttraction({-a, -a, -h}, {a, a, 0.0}, kStandardDensityKgM3);
    EXPECT_GE(g, previous) << a;  // (at 1e9 m the steps fall below double resolution)
    EXPECT_LE(g, slab * (1 + 1e-12)) << a;
    previous = g;
  }
  EXPECT_NEAR(previous / slab, 1.0, 1e-7);
}

TEST(Prism, MassAboveAttractsUpward) {
  EXPECT_LT(PrismDownwardAttraction({-5, -5, 1}, {5, 5, 3}, kStandardDensityKgM3), 0.0);
  EXPECT_NEAR(PrismDownwardAttraction({-5, -5, 1}, {5, 5, 3}, kStandardDensityKgM3),
              -PrismDownwardAttraction({-5, -5, -3}, {5, 5, -1}, kStandardDensityKgM3), 1e-18);
}

// Superposition: at a corner of a 2a x 2a prism, a quarter of the attraction at the centre of
// the 4a x 4a prism of the same height.
TEST(Prism, CornerIsAQuarterOfTheCentreOfTheDoubledPrism) {
  const double a = 7.5, h = 4.0;
  const double corner =
      PrismDownwardAttraction({0, 0, -h}, {2 * a, 2 * a, 0}, kStandardDensityKgM3);
  const double centre =
      PrismDownwardAttraction({-2 * a, -2 * a, -h}, {2 * a, 2 * a, 0}, kStandardDensityKgM3);
  EXPECT_NEAR(corner, 0.25 * centre, 1e-12 * centre);
}

// Far away a prism is a point mass, G M z / r^3 (to its quadrupole term, (size / r)^2 ~ 3e-5
// here), and still adds up exactly from its eight halves (no cancellation at 540 m).
TEST(Prism, FarAwayActsAsAPointMassAndStillAddsUp) {
  const Eigen::Vector3d c(300.0, -400.0, -200.0);
  const Eigen::Vector3d half(1.0, 1.5, 0.5);
  const double mass = kStandardDensityKgM3 * 8 * half.prod();
  const double point = kG * mass * (-c.z()) / std::pow(c.norm(), 3);
  const double whole = PrismDownwardAttraction(c - half, c + half, kStandardDensityKgM3);
  EXPECT_NEAR(whole, point, 3e-5 * point);
  double parts = 0.0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector3d lo =
            c - half + Eigen::Vector3d(i * half.x(), j * half.y(), k * half.z());
        parts += PrismDownwardAttraction(lo, lo + half, kStandardDensityKgM3);
      }
  EXPECT_NEAR(parts, whole, 1e-9 * whole);
}

// On a vertex, an edge, a face and inside a prism: finite, and continuous as the point moves
// onto them from outside.
TEST(Prism, FiniteAndContinuousOnVerticesEdgesAndFaces) {
  const Eigen::Vector3d lo(0, 0, -3), hi(4, 5, 0);
  for (const Eigen::Vector3d& at :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(2, 2.5, 0),
        Eigen::Vector3d(0, 0, -3), Eigen::Vector3d(4, 5, -1.5), Eigen::Vector3d(2, 2.5, -1.5)}) {
    const double on = PrismDownwardAttraction(lo - at, hi - at, kStandardDensityKgM3);
    ASSERT_TRUE(std::isfinite(on)) << at.transpose();
    for (const Eigen::Vector3d& d :
         {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(-1, 0.5, 2), Eigen::Vector3d(0.3, -1, -1)}) {
      const Eigen::Vector3d near = at + 1e-7 * d.normalized();
      const double g = PrismDownwardAttraction(lo - near, hi - near, kStandardDensityKgM3);
      EXPECT_NEAR(g, on, 1e-6 * std::abs(kG * kStandardDensityKgM3 * 5.0)) << at.transpose();
    }
  }
}

// A point a hair off an edge of a flat prism (b^2 << z^2 in the logarithms): still finite
// and continuous with the point on the edge.
TEST(Prism, FiniteAHairOffAnEdge) {
  const double on = PrismDownwardAttraction({-1, 0, -0.08}, {-0.9, 0.1, 0}, kStandardDensityKgM3);
  const double off =
      PrismDownwardAttraction({-1, -1.4e-16, -0.08}, {-0.9, 0.1, 0}, kStandardDensityKgM3);
  ASSERT_TRUE(std::isfinite(off));
  EXPECT_NEAR(off, on, 1e-12 * std::abs(on));
}

// Symmetry: a point at the centre of a cube feels nothing vertically.
// The line-mass far field: below 1e-4 relative from 5 sides on, 2e-5 from 10, and falling as
// (side / distance)^4 once the distance also dwarfs the column's height; for mass below,
// above and across the point's height.
TEST(Prism, FarFieldLineMassesErrorFallsAsTheFourthPowerOfSideOverDistance) {
  for (const auto& [z1, z2] : {std::pair{-3.0, -0.5}, std::pair{0.2, 4.0}, std::pair{-1.0, 2.0}}) {
    double previous = 0.0;
    for (double r : {5.0, 10.0, 20.0, 40.0, 80.0}) {
      const Eigen::Vector3d lo(r - 0.5, -0.5, z1), hi(r + 0.5, 0.5, z2);
      const double exact = PrismDownwardAttraction(lo, hi, kStandardDensityKgM3);
      const double error =
          std::abs(PrismDownwardAttractionFarField(lo, hi, kStandardDensityKgM3) / exact - 1.0);
      EXPECT_LT(error, r >= 10.0 ? 2e-5 : 1e-4) << z1 << " " << r;
      if (r >= 40.0) {
        EXPECT_NEAR(error / previous, 1.0 / 16, 0.015) << z1 << " " << r;
      }
      previous = error;
    }
  }
}

TEST(Prism, NoVerticalPullAtTheCentreOfACube) {
  EXPECT_NEAR(PrismDownwardAttraction({-1, -1, -1}, {1, 1, 1}, kStandardDensityKgM3), 0.0, 1e-20);
}

}  // namespace
}  // namespace ts
