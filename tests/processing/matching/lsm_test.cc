// Least-squares matching against known answers: templates made from an analytic texture by a
// known affine and radiometric transformation, so the true parameters are exact.
#include "processing/matching/lsm.h"

#include <gtest/gtest.h>

#include <random>

namespace ts {
namespace {

// A smooth random texture: Gaussian blobs of 1.5-4 px, values about 20-230.
struct BlobTexture {
  explicit BlobTexture(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-10, 110), sigma(1.5, 4.0), amp(-60, 60);
    for (int i = 0; i < 900; ++i) blobs.push_back({pos(rng), pos(rng), sigma(rng), amp(rng)});
  }
  double operator()(double x, double y) const {
    double v = 128.0;
    for (const Blob& b : blobs) {
      const double d2 = (x - b.x) * (x - b.x) + (y - b.y) * (y - b.y);
      if (d2 < 25 * b.s * b.s) v += b.a * std::exp(-d2 / (2 * b.s * b.s));
    }
    return v;
  }
  struct Blob {
    double x, y, s, a;
  };
  std::vector<Blob> blobs;
};

cv::Mat Sampled(const BlobTexture& t, int size) {
  cv::Mat m(size, size, CV_32FC1);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) m.at<float>(y, x) = static_cast<float>(t(x, y));
  return m;
}

// Template pixel (cx + x, cy + y) shows r0 + r1 F(a0 + a1 x + a2 y, b0 + b1 x + b2 y).
cv::Mat Template(const BlobTexture& t, const Eigen::Matrix<double, 8, 1>& p, int size, int cx,
                 int cy) {
  cv::Mat m(size, size, CV_32FC1, cv::Scalar(0));
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = x - cx, v = y - cy;
      m.at<float>(y, x) = static_cast<float>(
          p[6] + p[7] * t(p[0] + p[1] * u + p[2] * v, p[3] + p[4] * u + p[5] * v));
    }
  return m;
}

Eigen::Matrix<double, 8, 1> Params(double a0, double a1, double a2, double b0, double b1, double b2,
                                   double r0, double r1) {
  Eigen::Matrix<double, 8, 1> p;
  p << a0, a1, a2, b0, b1, b2, r0, r1;
  return p;
}

class Lsm : public ::testing::Test {
 protected:
  BlobTexture texture_{3};
  cv::Mat search_ = Sampled(texture_, 100);
};

// Bilinear resampling of the search window biases the match by up to ~0.015 px near half-pixel
// shifts on this texture (and lowers its contrast, which r1 absorbs): the tolerances below.
TEST_F(Lsm, RecoversASubPixelShift) {
  for (const auto& [dx, dy] :
       {std::pair{0.37, -0.21}, std::pair{-0.45, 0.48}, std::pair{0.0, 0.0}}) {
    const auto truth = Params(50 + dx, 1, 0, 47 + dy, 0, 1, 0, 1);
    const cv::Mat templ = Template(texture_, truth, 31, 15, 15);
    const LsmResult r = MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {51, 46});
    ASSERT_TRUE(r.ok) << r.why;
    EXPECT_NEAR(r.position_px.x(), 50 + dx, 0.02);
    EXPECT_NEAR(r.position_px.y(), 47 + dy, 0.02);
    EXPECT_GT(r.correlation, 0.999);
  }
}

TEST_F(Lsm, RecoversAffineAndRadiometricParameters) {
  const auto truth = Params(52.3, 1.06, 0.08, 44.7, -0.05, 0.94, 12.0, 0.8);
  const cv::Mat templ = Template(texture_, truth, 31, 15, 15);
  LsmOptions o;
  o.half_window_px = 10;
  const LsmResult r = MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {53.5, 44.0}, o);
  ASSERT_TRUE(r.ok) << r.why;
  EXPECT_NEAR(r.position_px.x(), 52.3, 0.02);
  EXPECT_NEAR(r.position_px.y(), 44.7, 0.02);
  for (int i : {1, 2, 4, 5}) EXPECT_NEAR(r.parameters[i], truth[i], 0.01) << i;
  EXPECT_NEAR(r.parameters[7], 0.8, 0.03);
  EXPECT_NEAR(r.parameters[6], 12.0, 4.0);
}

// Starting from a neighbour's shape (here the true one, as on a uniformly slanted surface) the
// fit lands on the same answer in fewer iterations than from the identity.
TEST_F(Lsm, AStartShapeSavesIterationsAndKeepsTheAnswer) {
  const auto truth = Params(52.3, 0.97, -0.3, 44.7, 0.0, 1.0, 5.0, 0.9);
  const cv::Mat templ = Template(texture_, truth, 31, 15, 15);
  LsmOptions o;
  o.half_window_px = 10;
  const LsmResult from_identity =
      MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {53.0, 45.0}, o);
  Eigen::Matrix2d shape;
  shape << truth[1], truth[2], truth[4], truth[5];
  const LsmResult from_shape =
      MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {53.0, 45.0}, o, &shape);
  ASSERT_TRUE(from_identity.ok) << from_identity.why;
  ASSERT_TRUE(from_shape.ok) << from_shape.why;
  EXPECT_NEAR(from_shape.position_px.x(), 52.3, 0.02);
  EXPECT_NEAR(from_shape.position_px.y(), 44.7, 0.02);
  EXPECT_NEAR(from_shape.position_px.x(), from_identity.position_px.x(), 0.005);
  EXPECT_LT(from_shape.iterations, from_identity.iterations);
}

// The reported sigma must describe the scatter of the matched position under image noise.
TEST_F(Lsm, SigmaDescribesTheScatterUnderNoise) {
  const auto truth = Params(48.6, 1, 0, 51.2, 0, 1, 0, 1);
  const cv::Mat clean = Template(texture_, truth, 31, 15, 15);
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  double sum_err2 = 0.0, sum_sigma2 = 0.0;
  const int trials = 200;
  for (int i = 0; i < trials; ++i) {
    cv::Mat templ = clean.clone();
    for (auto it = templ.begin<float>(); it != templ.end<float>(); ++it) *it += noise(rng);
    const LsmResult r = MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {49, 51});
    ASSERT_TRUE(r.ok) << r.why;
    sum_err2 += std::pow(r.position_px.x() - 48.6, 2);
    sum_sigma2 += r.sigma_x_px * r.sigma_x_px;
  }
  const double ratio = std::sqrt(sum_err2 / sum_sigma2);
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 1.4);
}

// Along rows only (rectified stereo): the x-affine is recovered on the template's row, with the
// precision the sigma claims, and it is more precise than the six-parameter fit on the same
// noisy windows (fewer unknowns).
TEST_F(Lsm, AlongRowsRecoversTheRowAffineWithAnHonestSigma) {
  const auto truth = Params(50.37, 0.96, -0.28, 47, 0, 1, 8.0, 0.9);
  const cv::Mat clean = Template(texture_, truth, 31, 15, 15);
  LsmOptions rows;
  rows.half_window_px = 10;
  rows.along_rows_only = true;
  const LsmResult exact =
      MatchLsm(clean, ComputeGradients(clean), {15, 15}, search_, {51, 47}, rows);
  ASSERT_TRUE(exact.ok) << exact.why;
  EXPECT_NEAR(exact.position_px.x(), 50.37, 0.02);
  EXPECT_EQ(exact.position_px.y(), 47.0);
  EXPECT_NEAR(exact.parameters[1], 0.96, 0.01);
  EXPECT_NEAR(exact.parameters[2], -0.28, 0.01);
  EXPECT_EQ(exact.sigma_y_px, 0.0);

  LsmOptions full = rows;
  full.along_rows_only = false;
  std::mt19937 rng(8);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  double err2_rows = 0.0, sigma2_rows = 0.0, err2_full = 0.0;
  const int trials = 200;
  for (int i = 0; i < trials; ++i) {
    cv::Mat templ = clean.clone();
    for (auto it = templ.begin<float>(); it != templ.end<float>(); ++it) *it += noise(rng);
    const ImageGradients g = ComputeGradients(templ);
    const LsmResult a = MatchLsm(templ, g, {15, 15}, search_, {51, 47}, rows);
    const LsmResult b = MatchLsm(templ, g, {15, 15}, search_, {51, 47}, full);
    ASSERT_TRUE(a.ok && b.ok) << a.why << " / " << b.why;
    err2_rows += std::pow(a.position_px.x() - 50.37, 2);
    sigma2_rows += a.sigma_x_px * a.sigma_x_px;
    err2_full += std::pow(b.position_px.x() - 50.37, 2);
  }
  const double ratio = std::sqrt(err2_rows / sigma2_rows);
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 1.4);
  EXPECT_LT(err2_rows, err2_full);
}

// A wide, low window (29 x 9, as for far ground) finds the same sub-pixel shift and x-affine.
TEST_F(Lsm, AWideLowWindowRecoversTheRowAffine) {
  const auto truth = Params(50.62, 1.03, 0.12, 47, 0, 1, 3.0, 1.1);
  const cv::Mat templ = Template(texture_, truth, 41, 20, 20);
  LsmOptions o;
  o.half_window_px = 14;
  o.half_height_px = 4;
  o.along_rows_only = true;
  const LsmResult r = MatchLsm(templ, ComputeGradients(templ), {20, 20}, search_, {50, 47}, o);
  ASSERT_TRUE(r.ok) << r.why;
  EXPECT_NEAR(r.position_px.x(), 50.62, 0.02);
  EXPECT_NEAR(r.parameters[1], 1.03, 0.01);
  EXPECT_NEAR(r.parameters[2], 0.12, 0.02);
  // The template must fit: 14 px beside the centre, 4 above it.
  const ImageGradients g = ComputeGradients(templ);
  EXPECT_EQ(MatchLsm(templ, g, {13, 20}, search_, {50, 47}, o).why,
            "template window leaves the image");
  EXPECT_NE(MatchLsm(templ, g, {20, 5}, search_, {50, 32}, o).why,
            "template window leaves the image");
  o.half_height_px = 1;
  std::string why;
  EXPECT_FALSE(o.Check(&why));
  EXPECT_NE(why.find("half_height_px"), std::string::npos);
}

TEST_F(Lsm, RejectsWhatCannotBeMatched) {
  const cv::Mat flat(60, 60, CV_32FC1, cv::Scalar(100));
  const LsmResult none = MatchLsm(flat, ComputeGradients(flat), {30, 30}, flat, {30, 30});
  EXPECT_FALSE(none.ok);
  EXPECT_NE(none.why.find("no texture"), std::string::npos) << none.why;

  const cv::Mat templ = Template(texture_, Params(50, 1, 0, 50, 0, 1, 0, 1), 31, 15, 15);
  const LsmResult edge = MatchLsm(templ, ComputeGradients(templ), {3, 15}, search_, {50, 50});
  EXPECT_FALSE(edge.ok);
  EXPECT_NE(edge.why.find("template window leaves the image"), std::string::npos);
  const LsmResult outside = MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {2, 50});
  EXPECT_FALSE(outside.ok);
  EXPECT_NE(outside.why.find("search window leaves the image"), std::string::npos);

  // A different texture altogether: whatever it converges to, it is not accepted.
  const BlobTexture other(99);
  const cv::Mat unrelated = Template(other, Params(50, 1, 0, 50, 0, 1, 0, 1), 31, 15, 15);
  EXPECT_FALSE(MatchLsm(unrelated, ComputeGradients(unrelated), {15, 15}, search_, {50, 50}).ok);

  LsmOptions bad;
  bad.half_window_px = 1;
  EXPECT_NE(MatchLsm(templ, ComputeGradients(templ), {15, 15}, search_, {50, 50}, bad)
                .why.find("half_window_px"),
            std::string::npos);
}

}  // namespace
}  // namespace ts
