// Occlusion edges with known geometry (issue 22): a near surface (a riser, a dike's crest)
// standing in front of far ground, as a rectified pair sees it.
//  - Beside it (a vertical edge, the near surface on the right): left of the edge the left
//    image shows the far ground, of which a band d_near - d_far pixels wide is hidden from the
//    right camera by the near surface.
//  - Below it (a brow, a horizontal edge): the near surface fills the rows below the edge, the
//    far ground those above; both cameras see both, and only the windows across the edge hold
//    two surfaces.
// A match in the hidden band, or one whose disparity is neither surface's at its pixel, is a
// stereo blunder at the edge: it puts a point in mid-air beside the brow or under the far
// ground.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "processing/matching/pair_matcher.h"
#include "tests/common/random_texture.h"

namespace ts {
namespace {

using testing::RandomTexture;

struct EdgeScene {
  int width = 640, height = 240;
  bool brow = false;              // false: the near surface right of column edge_px
  double edge_px = 360.0;         // column (or, for a brow, row) where the near surface begins
  double near_disparity = 56.25;  // f B / Z: 1500 px x 0.3 m over 8 m
  double far_disparity = 22.5;    // ... over 20 m
  unsigned seed = 1;

  // > 0: instead of one brow, lips every stripe_px rows from edge_px to band_end_px (a slope
  // striped with small steps), the near surface in every other stripe.
  int stripe_px = 0;
  double band_end_px = 0.0;

  bool NearAt(double u, double v) const {
    if (stripe_px > 0)
      return v >= edge_px && v < band_end_px &&
             static_cast<int>(std::floor((v - edge_px) / stripe_px)) % 2 == 0;
    return (brow ? v : u) >= edge_px;
  }
  double TrueDisparity(double u, double v) const {
    return NearAt(u, v) ? near_disparity : far_disparity;
  }
  // The far ground the right camera cannot see: it lies behind the near surface.
  bool HiddenFromRight(double u, double v) const {
    return !brow && !NearAt(u, v) && u >= edge_px - (near_disparity - far_disparity);
  }
  // Where a whole least-squares window (half width h) sees one surface in both images.
  bool WindowOnOneSurface(double u, double v, int h) const {
    if (stripe_px > 0) {
      for (double row = v - h - 1; row <= v + h + 1; ++row)
        if (NearAt(u, row) != NearAt(u, v)) return false;
      return true;
    }
    if (brow) return std::abs(v - edge_px) > h + 1;
    return NearAt(u, v) ? u - h > edge_px : u + h < edge_px - (near_disparity - far_disparity);
  }
};

// Each surface carries its own texture, fixed to it; the right camera sees the point of the
// left image's pixel (u, v) at u - d. Beside a vertical edge, the near surface covers the right
// image from column edge - d_near on.
void RenderPair(const EdgeScene& s, cv::Mat* left, cv::Mat* right) {
  const cv::Mat near = RandomTexture(s.width + 128, s.height, s.seed);
  const cv::Mat far = RandomTexture(s.width + 128, s.height, s.seed + 100);
  cv::Mat near_x(s.height, s.width, CV_32FC1), far_x(s.height, s.width, CV_32FC1),
      rows(s.height, s.width, CV_32FC1);
  *left = cv::Mat(s.height, s.width, CV_32FC1);
  *right = cv::Mat(s.height, s.width, CV_32FC1);
  for (int v = 0; v < s.height; ++v)
    for (int u = 0; u < s.width; ++u) {
      near_x.at<float>(v, u) = static_cast<float>(u + s.near_disparity);
      far_x.at<float>(v, u) = static_cast<float>(u + s.far_disparity);
      rows.at<float>(v, u) = static_cast<float>(v);
      left->at<float>(v, u) = (s.NearAt(u, v) ? near : far).at<float>(v, u);
    }
  cv::Mat right_near, right_far;
  cv::remap(near, right_near, near_x, rows, cv::INTER_CUBIC, cv::BORDER_REFLECT);
  cv::remap(far, right_far, far_x, rows, cv::INTER_CUBIC, cv::BORDER_REFLECT);
  for (int v = 0; v < s.height; ++v)
    for (int u = 0; u < s.width; ++u)
      right->at<float>(v, u) =
          (s.NearAt(u + s.near_disparity, v) ? right_near : right_far).at<float>(v, u);
  cv::RNG rng(s.seed + 7);
  for (cv::Mat* image : {left, right}) {
    cv::Mat noise(image->size(), CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
    *image += noise;
  }
}

struct EdgeMatches {
  int on_one_surface = 0;  // matched where a whole window sees one surface
  int in_hidden_band = 0, off_both_surfaces = 0;
  double worst_off_px = 0.0;
};

EdgeMatches MatchAcrossTheEdge(const EdgeScene& s, PairMatchOptions o = {}) {
  cv::Mat left, right;
  RenderPair(s, &left, &right);
  Rectification r;
  r.focal_px = 1500.0, r.baseline_m = 0.3, r.width_px = s.width, r.height_px = s.height;
  o.min_disparity_px = 0;
  o.max_disparity_px = 96;
  EdgeMatches out;
  for (const StereoMatch& m : MatchRectifiedPair(r, left, right, o, nullptr)) {
    const double u = m.left_px.x(), v = m.left_px.y();
    if (s.HiddenFromRight(u, v)) {
      ++out.in_hidden_band;
      continue;
    }
    const double off = std::abs(m.disparity_px - s.TrueDisparity(u, v));
    if (off > std::max(0.5, 4.0 * m.sigma_disparity_px)) {
      ++out.off_both_surfaces;
      out.worst_off_px = std::max(out.worst_off_px, off);
    }
    out.on_one_surface += s.WindowOnOneSurface(u, v, o.lsm.half_window_px);
  }
  return out;
}

// Matches a 4 x 4 grid of points would give where whole windows see one surface and both
// images hold them (the far ground's first d_far columns are off the right image).
double PointsWithOneSurfaceInView(const EdgeScene& s, int h) {
  int n = 0;
  for (int v = h; v < s.height - h; ++v)
    for (int u = static_cast<int>(s.far_disparity) + h; u < s.width - h; ++u)
      n += !s.HiddenFromRight(u, v) && s.WindowOnOneSurface(u, v, h);
  return n / 16.0;
}

TEST(OcclusionEdge, NoMatchIsMadeWhereOnlyTheLeftCameraSeesOrBetweenTheSurfaces) {
  // Three depth steps: a riser at 8 m before a tread at 20 m, a dike's crest at 10 m before
  // the field at 14 m, a brow at 5 m before ground at 30 m; each beside and below, for three
  // textures.
  const std::pair<double, double> steps[] = {{56.25, 22.5}, {45.0, 32.14}, {90.0, 15.0}};
  for (const bool brow : {false, true})
    for (unsigned seed = 1; seed <= 3; ++seed)
      for (const auto& [near_d, far_d] : steps) {
        EdgeScene s;
        s.brow = brow, s.seed = seed, s.near_disparity = near_d, s.far_disparity = far_d;
        if (brow) s.edge_px = 120.0;
        const EdgeMatches m = MatchAcrossTheEdge(s);
        SCOPED_TRACE(std::string(brow ? "brow" : "beside") + ", seed " + std::to_string(seed) +
                     ", disparities " + std::to_string(near_d) + " / " + std::to_string(far_d));
        EXPECT_EQ(m.in_hidden_band, 0);
        EXPECT_EQ(m.off_both_surfaces, 0) << "worst " << m.worst_off_px << " px off";
        // Away from the edge both surfaces are matched: the test cannot pass by matching
        // nothing.
        EXPECT_GT(m.on_one_surface, 0.5 * PointsWithOneSurfaceInView(s, 10));
      }
}

// A brow whose step in depth is below what the pyramid's map resolves (its disparities come in
// steps of two pixels, compared with a slack of four): a lip at 17.6 m before ground at 20 m,
// 25.5 against 22.5 px. Windows across it pass the other-surface test, and least squares
// blends the two; their grey residuals, several times their neighbours', give them away.
// Least squares blends windows across the edges of s; the residual check must find them all
// and keep half of what whole windows on one surface would give.
void ExpectTheResidualCheckFindsTheBlends(const EdgeScene& s) {
  PairMatchOptions without;
  without.max_residual_ratio = 0.0;
  const EdgeMatches blended = MatchAcrossTheEdge(s, without);
  const EdgeMatches m = MatchAcrossTheEdge(s);
  EXPECT_GT(blended.off_both_surfaces, 0);  // the test has something to find
  EXPECT_EQ(m.off_both_surfaces, 0) << "worst " << m.worst_off_px << " px off";
  EXPECT_GT(m.on_one_surface, 0.5 * PointsWithOneSurfaceInView(s, 10));
}

TEST(OcclusionEdge, ABrowTooSmallForThePyramidIsFoundByTheFitsResiduals) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    EdgeScene s;
    s.brow = true, s.edge_px = 120.0, s.seed = seed;
    s.near_disparity = 25.5, s.far_disparity = 22.5;
    SCOPED_TRACE("seed " + std::to_string(seed));
    ExpectTheResidualCheckFindsTheBlends(s);
  }
}

// A band of such brows every 12 rows (a slope striped with lips, 25.5 against 22.5 px), 160
// rows of it between far ground above and below: every window in the band holds a lip or two,
// so the matches around a blend are blends too, and its residual is like theirs (judged by
// them alone, about 1,800 of some 2,000 blends stay). The rest of the pair says what one
// surface leaves.
TEST(OcclusionEdge, ABandOfBrowsIsFoundByThePairsResiduals) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    EdgeScene s;
    s.brow = true, s.height = 480, s.edge_px = 160.0, s.band_end_px = 320.0, s.stripe_px = 12;
    s.near_disparity = 25.5, s.far_disparity = 22.5, s.seed = seed;
    SCOPED_TRACE("seed " + std::to_string(seed));
    ExpectTheResidualCheckFindsTheBlends(s);
  }
}

}  // namespace
}  // namespace ts
