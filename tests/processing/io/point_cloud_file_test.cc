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

// A header is read and checked before PCL reserves anything for what it declares: PCL's
// readers crashed on an empty .pcd and asked for 96 GB for a PLY declaring 4e9 vertices.
TEST(PointCloudFile, CorruptHeadersAreRefusedBeforeAnythingIsReserved) {
  testing::TempDir dir;
  auto error_of = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name, std::ios::binary) << text;
    const auto r = ReadPointCloudXyz(dir / name);
    EXPECT_FALSE(r) << name;
    return r ? std::string() : r.error();
  };
  const std::string ply_header = "ply\nformat binary_little_endian 1.0\nelement vertex ";
  const std::string xyz = "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  EXPECT_EQ(error_of("empty.pcd", ""), dir / "empty.pcd" + ": empty file");
  EXPECT_NE(
      error_of("huge.ply", ply_header + "4000000000" + xyz).find("declares 4000000000 points"),
      std::string::npos);
  // 100 points of 12 bytes declared, 3 present.
  EXPECT_NE(error_of("short.ply", ply_header + "100" + xyz + std::string(36, '\0'))
                .find("truncated (fewer bytes than its header's 100 points need)"),
            std::string::npos);
  EXPECT_NE(
      error_of("open.ply", ply_header + "3\nproperty float x\n").find("no complete PLY header"),
      std::string::npos);
  const std::string pcd =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1000000\n"
      "HEIGHT 1\nPOINTS 1000000\nDATA binary\n";
  EXPECT_NE(error_of("short.pcd", pcd + std::string(12, '\0')).find("truncated"),
            std::string::npos);
}

}  // namespace
}  // namespace ts
