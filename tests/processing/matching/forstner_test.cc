#include "processing/matching/forstner.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <random>
#include <stdexcept>
#include "tests/common/random_texture.h"

namespace ts {
namespace {

// A bright quadrant x > cx, y > cy, anti-aliased by 16x16 supersampling, then blurred.
cv::Mat Corner(double cx, double cy) {
  cv::Mat m(80, 80, CV_32FC1);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      int inside = 0;
      for (int sy = 0; sy < 16; ++sy)
        for (int sx = 0; sx < 16; ++sx)
          inside += (x - 0.5 + (sx + 0.5) / 16 > cx) && (y - 0.5 + (sy + 0.5) / 16 > cy);
      m.at<float>(y, x) = 40.0f + 160.0f * inside / 256.0f;
    }
  cv::GaussianBlur(m, m, {0, 0}, 0.8);
  return m;
}

using testing::RandomTexture;

TEST(Forstner, LocatesACornerToSubPixelPrecision) {
  for (const auto& [cx, cy] : {std::pair{40.3, 37.6}, std::pair{38.75, 41.1}}) {
    ForstnerOptions o;
    o.cell_px = 80;  // one point for the whole image: the corner
    const auto points = DetectForstner(Corner(cx, cy), o);
    ASSERT_EQ(points.size(), 1u);
    EXPECT_NEAR(points[0].position_px.x(), cx, 0.15);
    EXPECT_NEAR(points[0].position_px.y(), cy, 0.15);
    EXPECT_GT(points[0].roundness, 0.5);
  }
}

TEST(Forstner, PointsAreSpreadOnTheGridNotClumped) {
  const cv::Mat image = RandomTexture(240, 160, 3);
  ForstnerOptions o;
  const auto points = DetectForstner(image, o);
  const int cells = ((240 - 16 + 7) / 8) * ((160 - 16 + 7) / 8);
  EXPECT_GT(points.size(), 0.5 * cells);  // texture everywhere: points nearly everywhere
  EXPECT_LE(points.size(), static_cast<size_t>(cells));
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j)
      EXPECT_GE((points[i].position_px - points[j].position_px).norm(), 4.0);  // half a cell
  // A denser grid gives more points, up to what the texture has maxima for (a quarter of the
  // cell area doubles the count here, not quadruples it).
  o.cell_px = 4;
  EXPECT_GT(DetectForstner(image, o).size(), 3 * points.size() / 2);
}

// Dense use: every textured cell gives its strongest pixel, still never two within half a
// cell; flat parts of the image give none.
TEST(Forstner, DenseModeGivesAPointInEveryTexturedCell) {
  cv::Mat image = RandomTexture(240, 160, 4);
  image.colRange(120, 240).setTo(100);  // right half flat
  ForstnerOptions o;
  o.cell_px = 4;
  o.local_maxima_only = false;
  o.min_roundness = 0.0;
  o.min_weight_factor = 0.01;
  const auto points = DetectForstner(image, o);
  const int textured_cells = ((120 - 8) / 4) * ((160 - 16) / 4);
  int left = 0;
  for (const InterestPoint& p : points) {
    EXPECT_LT(p.position_px.x(), 120 + o.half_window_px + o.locate_half_window_px) << "flat half";
    left += p.position_px.x() < 120 - 4;
  }
  // Picks in neighbouring cells closer than half a cell keep only the stronger one.
  EXPECT_GT(left, 0.5 * textured_cells);
  // On smooth texture (as far ground looks) local maxima of w are sparse: the classic
  // operator finds far fewer points than one per cell.
  cv::Mat smooth;
  cv::GaussianBlur(image, smooth, {0, 0}, 3.0);
  const size_t dense = DetectForstner(smooth, o).size();
  o.local_maxima_only = true;
  EXPECT_GT(dense, 2 * DetectForstner(smooth, o).size());
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j)
      EXPECT_GE((points[i].position_px - points[j].position_px).norm(), 2.0);
}

TEST(Forstner, NoPointsOnFlatGroundOrStraightEdges) {
  EXPECT_TRUE(DetectForstner(cv::Mat(100, 100, CV_8UC1, cv::Scalar(90)), {}).empty());
  cv::Mat edge(100, 100, CV_32FC1, cv::Scalar(50));
  edge.colRange(50, 100).setTo(200);
  cv::GaussianBlur(edge, edge, {0, 0}, 1.0);
  for (const InterestPoint& p : DetectForstner(edge, {})) EXPECT_GE(p.roundness, 0.5);
  EXPECT_TRUE(DetectForstner(edge, {}).empty());
}

TEST(Forstner, RejectsBadOptions) {
  ForstnerOptions o;
  o.cell_px = 1;
  EXPECT_THROW(DetectForstner(cv::Mat(50, 50, CV_8UC1), o), std::invalid_argument);
}

}  // namespace
}  // namespace ts
