#pragma once
// Point cloud files: any PCD or PLY with x, y, z fields (float or double) in (through PCL),
// binary little-endian PLY with double coordinates and per-point attributes out (written to
// a temporary name and renamed, like every product). PCL stays inside the .cc.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

// The most points a cloud file may declare: a station holds about 0.3 million, an airborne
// lidar tile tens of millions; more is a corrupt header, refused before memory is reserved.
constexpr double kMaxCloudPoints = 200e6;

// The x, y, z of every point of a .pcd or .ply file (by extension). Errors name the file: an
// empty file, a header that does not end or declares more points than kMaxCloudPoints or than
// the file's bytes can hold, a body PCL cannot parse, a missing x, y or z.
Result<std::vector<Eigen::Vector3d>> ReadPointCloudXyz(const std::string& path);

// A per-point attribute column of a PLY file: exactly one of the vectors is filled, with
// one value per point.
struct PlyColumn {
  std::string name;
  std::vector<float> f32;
  std::vector<int32_t> i32;
  std::vector<uint8_t> u8;
};

// x, y, z as double (coordinates unchanged to the last bit of their input), then the columns.
Status WritePly(const std::string& path, const std::vector<Eigen::Vector3d>& points,
                const std::vector<PlyColumn>& columns = {});

}  // namespace ts
