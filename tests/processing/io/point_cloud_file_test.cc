#include "processing/io/point_cloud_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/isprs_sample.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

TEST(PointCloudFile, PlyRoundTripKeepsCoordinatesToTheLastBit) {
  testing::TempDir dir;
  const std::vector<Eigen::Vector3d> points = {{512743.625, 5403547.5, 308.72}, {0.1, -0.2, 1e-9}};
  PlyColumn pair{"pair", {}, {3, 11}, {}};
  ASSERT_TRUE(WritePly(dir / "a.ply", points, {pair}));
  const auto back = ReadPointCloudXyz(dir / "a.ply");
  ASSERT_TRUE(back) << back.error();
  ASSERT_EQ(back->size(), 2u);
  for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ((*back)[i], points[i]);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.ply.tmp-pcl"));
}

TEST(PointCloudFile, ReadsCompressedPcd) {
  const auto points = ReadPointCloudXyz(testing::IsprsPath("samp21"));
  ASSERT_TRUE(points) << points.error();
  EXPECT_GT(points->size(), 5000u);
  EXPECT_GT((*points)[0].y(), 5e6);  // UTM northing
}

TEST(PointCloudFile, BadInputNamesTheFile) {
  testing::TempDir dir;
  EXPECT_NE(ReadPointCloudXyz(dir / "missing.ply").error().find("missing.ply"), std::string::npos);
  std::ofstream(dir / "junk.ply") << "ply\nformat nonsense\n";
  const auto junk = ReadPointCloudXyz(dir / "junk.ply");
  ASSERT_FALSE(junk);
  EXPECT_NE(junk.error().find("junk.ply"), std::string::npos);
  std::ofstream(dir / "cloud.xyz") << "1 2 3\n";
  EXPECT_NE(ReadPointCloudXyz(dir / "cloud.xyz").error().find(".pcd or .ply"), std::string::npos);
  const std::vector<Eigen::Vector3d> one = {{1, 2, 3}};
  PlyColumn wrong{"sigma", {1.0f, 2.0f}, {}, {}};
  EXPECT_FALSE(WritePly(dir / "b.ply", one, {wrong}));
}

}  // namespace
}  // namespace ts
