#include "processing/io/point_cloud_file.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "processing/io/atomic_file.h"

namespace ts {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == suffix;
}

template <typename T>
double Load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return static_cast<double>(v);
}

// Value of a scalar field of any numeric PCL type.
double FieldValue(const uint8_t* p, uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::FLOAT32:
      return Load<float>(p);
    case pcl::PCLPointField::FLOAT64:
      return Load<double>(p);
    case pcl::PCLPointField::INT32:
      return Load<int32_t>(p);
    case pcl::PCLPointField::UINT32:
      return Load<uint32_t>(p);
    case pcl::PCLPointField::INT16:
      return Load<int16_t>(p);
    case pcl::PCLPointField::UINT16:
      return Load<uint16_t>(p);
    case pcl::PCLPointField::INT8:
      return Load<int8_t>(p);
    case pcl::PCLPointField::UINT8:
      return Load<uint8_t>(p);
    default:
      return NAN;
  }
}

// Bytes of one value of a PLY property type (0: unknown).
size_t PlyTypeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// What a cloud file's header declares: its points and the fewest bytes the body needs for
// them (compressed bodies: 0, unknown).
struct DeclaredCloud {
  double points = 0.0;
  double min_body_bytes = 0.0;
  size_t header_bytes = 0;
};

// The header, read line by line up to its end, before any parser reserves memory for what it
// declares (PCL's readers trust the count: a PLY declaring 4e9 vertices, a PCD with none).
Result<DeclaredCloud> ReadDeclaredCloud(const std::string& path, bool ply) {
  std::ifstream in(path, std::ios::binary);
  DeclaredCloud d;
  std::string line, format;
  double record_bytes = 0.0, fields = 0.0, width = 1.0, height = 1.0;
  bool in_vertex = false, ended = false, points_given = false;
  for (int lines = 0; lines < 1000 && std::getline(in, line); ++lines) {
    d.header_bytes += line.size() + 1;
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (ply) {
      if (key == "format") words >> format;
      if (key == "element") {
        std::string name;
        words >> name;
        in_vertex = name == "vertex";
        if (in_vertex) words >> d.points;
      }
      if (key == "property" && in_vertex) {
        std::string type;
        words >> type;
        fields += 1.0;
        record_bytes += type == "list" ? 1.0 : static_cast<double>(PlyTypeBytes(type));
      }
      if (key == "end_header") ended = true;
    } else {
      if (key == "SIZE" || key == "COUNT") {
        std::vector<double> v;
        for (double x; words >> x;) v.push_back(x);
        if (key == "SIZE") record_bytes = 0.0, fields = static_cast<double>(v.size());
        for (size_t i = 0; i < v.size(); ++i) record_bytes += key == "SIZE" ? v[i] : 0.0;
      }
      if (key == "WIDTH") words >> width;
      if (key == "HEIGHT") words >> height;
      if (key == "POINTS") words >> d.points, points_given = true;
      if (key == "DATA") words >> format, ended = true;
    }
    if (!words && !words.eof()) return Error{path + ": header line '" + line + "' unreadable"};
    if (ended) break;
  }
  if (!ended) return Error{path + ": no complete " + (ply ? "PLY" : "PCD") + " header"};
  if (!ply && !points_given) d.points = width * height;
  if (!(d.points >= 0.0)) return Error{path + ": header declares a negative number of points"};
  const bool ascii = format == "ascii";
  if (format != "binary_compressed")
    d.min_body_bytes = d.points * (ascii ? 2.0 * fields : record_bytes);
  return d;
}

}  // namespace

Result<std::vector<Eigen::Vector3d>> ReadPointCloudXyz(const std::string& path) {
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  if (!std::filesystem::is_regular_file(path)) return Error{path + ": no such file"};
  const bool ply = EndsWith(path, ".ply");
  if (!ply && !EndsWith(path, ".pcd"))
    return Error{path + ": not a point cloud file (expected .pcd or .ply)"};
  const uintmax_t bytes = std::filesystem::file_size(path);
  if (bytes == 0) return Error{path + ": empty file"};
  const Result<DeclaredCloud> declared = ReadDeclaredCloud(path, ply);
  if (!declared) return Error{declared.error()};
  if (declared->points > kMaxCloudPoints)
    return Error{path + ": header declares " + std::to_string(std::llround(declared->points)) +
                 " points, more than the " + std::to_string(std::llround(kMaxCloudPoints)) +
                 " a cloud may have here"};
  if (declared->header_bytes + declared->min_body_bytes > static_cast<double>(bytes))
    return Error{path + ": truncated (fewer bytes than its header's " +
                 std::to_string(std::llround(declared->points)) + " points need)"};
  pcl::PCLPointCloud2 cloud;
  int status = -1;
  if (!ply) {
    status = pcl::io::loadPCDFile(path, cloud);
  } else {
    status = pcl::io::loadPLYFile(path, cloud);
  }
  if (status < 0) return Error{path + ": unreadable point cloud (PCL could not parse it)"};
  const pcl::PCLPointField* xyz[3] = {nullptr, nullptr, nullptr};
  for (const pcl::PCLPointField& f : cloud.fields)
    for (int k = 0; k < 3; ++k)
      if (f.name == std::string(1, "xyz"[k])) xyz[k] = &f;
  for (int k = 0; k < 3; ++k)
    if (!xyz[k]) return Error{path + ": field " + std::string(1, "xyz"[k]) + " missing"};
  const size_t n = static_cast<size_t>(cloud.width) * cloud.height;
  if (cloud.data.size() < n * cloud.point_step)
    return Error{path + ": truncated (fewer bytes than its header's points)"};
  std::vector<Eigen::Vector3d> points(n);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = cloud.data.data() + i * cloud.point_step;
    for (int k = 0; k < 3; ++k) points[i][k] = FieldValue(p + xyz[k]->offset, xyz[k]->datatype);
  }
  return points;
}

// The binary PLY body is the records as they lie in memory (little-endian, packed), so it is
// written straight from one buffer: PCL's writer formats element by element and took 0.15 s
// for a station's 250 k points, most of the time between the last pair and the products.
Status WritePly(const std::string& path, const std::vector<Eigen::Vector3d>& points,
                const std::vector<PlyColumn>& columns) {
  static_assert(std::endian::native == std::endian::little, "PLY bodies are little-endian");
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by topostation\n";
  header += "element vertex " + std::to_string(points.size()) + "\n";
  for (const char* axis : {"x", "y", "z"}) header += std::string("property double ") + axis + "\n";
  size_t record = 24;
  for (const PlyColumn& c : columns) {
    const size_t filled = !c.f32.empty() + !c.i32.empty() + !c.u8.empty();
    const size_t size = c.f32.size() + c.i32.size() + c.u8.size();
    if (filled > 1 || size != points.size())
      return Error{path + ": column " + c.name + " does not have one value per point"};
    const char* type = !c.f32.empty() ? "float" : !c.i32.empty() ? "int" : "uchar";
    header += std::string("property ") + type + " " + c.name + "\n";
    record += c.u8.empty() ? 4 : 1;
  }
  header += "end_header\n";
  std::string bytes(header.size() + record * points.size(), '\0');
  std::memcpy(bytes.data(), header.data(), header.size());
  for (size_t i = 0; i < points.size(); ++i) {
    char* p = bytes.data() + header.size() + i * record;
    std::memcpy(p, points[i].data(), 24);
    p += 24;
    for (const PlyColumn& c : columns) {
      if (!c.f32.empty()) std::memcpy(p, &c.f32[i], 4), p += 4;
      if (!c.i32.empty()) std::memcpy(p, &c.i32[i], 4), p += 4;
      if (!c.u8.empty()) *p++ = static_cast<char>(c.u8[i]);
    }
  }
  return WriteFileAtomically(path, bytes);
}

}  // namespace ts
