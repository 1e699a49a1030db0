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
#include <map>
#include <set>
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

// The header's lines, up to and with the one for which `last` holds (at most 1000 lines).
struct HeaderLines {
  std::vector<std::string> lines;
  size_t bytes = 0;
  bool ended = false;
};

template <class Last>
HeaderLines ReadHeaderLines(const std::string& path, Last last) {
  std::ifstream in(path, std::ios::binary);
  HeaderLines h;
  std::string line;
  while (h.lines.size() < 1000 && std::getline(in, line)) {
    h.bytes += line.size() + 1;
    h.lines.push_back(line);
    if (last(line)) return h.ended = true, h;
  }
  return h;
}

// A header line as an error message can show it: non-printable bytes as '?', at most 60.
std::string Shown(const std::string& line) {
  std::string shown = line.substr(0, 60);
  for (char& c : shown)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return shown + (line.size() > 60 ? "..." : "");
}

bool Whole(double v, double max) { return v >= 0.0 && v <= max && v == std::floor(v); }

// The whole header is checked before PCL reads the file: PCL's readers trust what they find
// (a PLY declaring 4e9 vertices is reserved; a PCD without its POINTS line crashes the binary
// reader), so anything not in the format's specification is refused here.
Result<DeclaredCloud> ReadDeclaredPly(const std::string& path) {
  const HeaderLines h =
      ReadHeaderLines(path, [](const std::string& l) { return l == "end_header"; });
  if (!h.ended || h.lines.empty() || h.lines[0] != "ply")
    return Error{path + ": no complete PLY header (ply ... end_header)"};
  DeclaredCloud d;
  d.header_bytes = h.bytes;
  std::string format, element;
  double record_bytes = 0.0, properties = 0.0;
  bool vertex = false;
  for (size_t i = 1; i + 1 < h.lines.size(); ++i) {
    std::istringstream words(h.lines[i]);
    std::string key, a, b, c;
    words >> key;
    const auto bad = [&] {
      return Error{path + ": PLY header line '" + Shown(h.lines[i]) + "' is not valid"};
    };
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      words >> format >> a;
      if ((format != "ascii" && format != "binary_little_endian" &&
           format != "binary_big_endian") ||
          a != "1.0")
        return bad();
    } else if (key == "element") {
      double count = -1.0;
      words >> element >> count;
      if (!words || !Whole(count, 1e15)) return bad();
      if (element == "vertex") vertex = true, d.points = count;
    } else if (key == "property") {
      words >> a >> b;
      if (a == "list") {
        words >> c;
        if (!PlyTypeBytes(b) || !PlyTypeBytes(c)) return bad();
      } else if (!PlyTypeBytes(a) || b.empty()) {
        return bad();
      }
      if (element.empty()) return bad();
      if (element == "vertex")
        properties += 1.0, record_bytes += a == "list" ? double(PlyTypeBytes(b)) : PlyTypeBytes(a);
    } else {
      return bad();
    }
  }
  if (format.empty()) return Error{path + ": PLY header without its format line"};
  if (!vertex) return Error{path + ": PLY header without a vertex element"};
  d.min_body_bytes = d.points * (format == "ascii" ? 2.0 * properties : record_bytes);
  return d;
}

Result<DeclaredCloud> ReadDeclaredPcd(const std::string& path) {
  const HeaderLines h =
      ReadHeaderLines(path, [](const std::string& l) { return l.rfind("DATA", 0) == 0; });
  if (!h.ended) return Error{path + ": no complete PCD header (up to its DATA line)"};
  DeclaredCloud d;
  d.header_bytes = h.bytes;
  std::map<std::string, std::vector<std::string>> values;
  for (const std::string& line : h.lines) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    std::string key;
    words >> key;
    static const std::set<std::string> kKeys = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                                "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
    if (!kKeys.count(key) || values.count(key))
      return Error{path + ": PCD header line '" + Shown(line) + "' is not valid"};
    std::vector<std::string>& v = values[key];
    for (std::string w; words >> w;) v.push_back(w);
  }
  for (const char* key : {"FIELDS", "SIZE", "TYPE", "WIDTH", "HEIGHT", "POINTS", "DATA"})
    if (!values.count(key) || values[key].empty())
      return Error{path + ": PCD header without its " + key + " line"};
  const size_t fields = values["FIELDS"].size();
  if (!values.count("COUNT")) values["COUNT"].assign(fields, "1");
  auto number = [](const std::string& w) {
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    return end && *end == '\0' ? v : -1.0;
  };
  double record_bytes = 0.0;
  for (const char* key : {"SIZE", "TYPE", "COUNT"})
    if (values[key].size() != fields)
      return Error{path + ": PCD header: " + key + " does not give one entry per field"};
  for (size_t i = 0; i < fields; ++i) {
    const double size = number(values["SIZE"][i]), count = number(values["COUNT"][i]);
    const std::string& type = values["TYPE"][i];
    if ((size != 1 && size != 2 && size != 4 && size != 8) || !Whole(count, 1e6) || count < 1 ||
        (type != "I" && type != "U" && type != "F"))
      return Error{path + ": PCD header: field " + values["FIELDS"][i] +
                   " has no valid SIZE, TYPE and COUNT"};
    record_bytes += size * count;
  }
  const double width = number(values["WIDTH"][0]), height = number(values["HEIGHT"][0]);
  d.points = number(values["POINTS"][0]);
  if (!Whole(width, 1e15) || !Whole(height, 1e15) || !Whole(d.points, 1e15) ||
      d.points != width * height)
    return Error{path + ": PCD header: POINTS must be WIDTH x HEIGHT, whole numbers"};
  const std::string& data = values["DATA"][0];
  if (data != "ascii" && data != "binary" && data != "binary_compressed")
    return Error{path + ": PCD header: DATA must be ascii, binary or binary_compressed"};
  if (data != "binary_compressed")
    d.min_body_bytes = d.points * (data == "ascii" ? 2.0 * fields : record_bytes);
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
  const Result<DeclaredCloud> declared = ply ? ReadDeclaredPly(path) : ReadDeclaredPcd(path);
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
