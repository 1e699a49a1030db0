#include "processing/dem/georeference.h"

#include <ogr_spatialref.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

namespace ts {

Eigen::Vector3d Georeference::ToWorld(const Eigen::Vector3d& p) const {
  const double c = std::cos(rotation_rad), s = std::sin(rotation_rad);
  return {scale * (c * p.x() - s * p.y()) + shift_m.x(),
          scale * (s * p.x() + c * p.y()) + shift_m.y(), p.z() + height_offset_m};
}

Result<Georeference> FitGeoreference(const std::vector<GroundControlPoint>& gcps,
                                     const std::string& crs_wkt) {
  if (gcps.size() < 2) return Error{"georeferencing needs at least two GCPs"};
  // Similarity as a linear problem in (a, b, tx, ty): E = a x - b y + tx, N = b x + a y + ty,
  // solved about the centroids.
  Eigen::Vector2d cs = Eigen::Vector2d::Zero(), cw = Eigen::Vector2d::Zero();
  double dz = 0.0;
  for (const GroundControlPoint& g : gcps) {
    cs += g.station_m.head<2>(), cw += g.world_m.head<2>();
    dz += g.world_m.z() - g.station_m.z();
  }
  const double n = static_cast<double>(gcps.size());
  cs /= n, cw /= n;
  double sxx = 0, a_num = 0, b_num = 0;
  for (const GroundControlPoint& g : gcps) {
    const Eigen::Vector2d p = g.station_m.head<2>() - cs, q = g.world_m.head<2>() - cw;
    sxx += p.squaredNorm();
    a_num += p.x() * q.x() + p.y() * q.y();
    b_num += p.x() * q.y() - p.y() * q.x();
  }
  if (!(sxx > 1e-6))
    return Error{"GCPs " + gcps.front().name + " .. " + gcps.back().name +
                 " share one horizontal position: the rotation is undetermined"};
  const double a = a_num / sxx, b = b_num / sxx;
  Georeference g;
  g.crs_wkt = crs_wkt;
  g.scale = std::hypot(a, b);
  g.rotation_rad = std::atan2(b, a);
  g.shift_m = cw - Eigen::Vector2d(a * cs.x() - b * cs.y(), b * cs.x() + a * cs.y());
  g.height_offset_m = dz / n;
  for (const GroundControlPoint& p : gcps)
    g.residuals_m.push_back((g.ToWorld(p.station_m) - p.world_m).norm());
  return g;
}

namespace {

Result<Eigen::Vector3d> ReadTriple(const YAML::Node& node, const std::string& where) {
  if (!node || !node.IsSequence() || node.size() != 3)
    return Error{where + ": must be a list of three numbers"};
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    try {
      v[k] = node[k].as<double>();
    } catch (const YAML::Exception&) {
      return Error{where + ": must be a list of three numbers"};
    }
    if (!std::isfinite(v[k])) return Error{where + ": must be finite"};
  }
  return v;
}

}  // namespace

Result<Georeference> LoadGeoreference(const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    return Error{file + ": cannot be read"};
  } catch (const YAML::Exception& e) {
    return Error{file + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + ")"};
  }
  if (!root.IsMap() || !root["crs"] || !root["crs"].IsScalar())
    return Error{file + ": crs: missing (e.g. EPSG:32633)"};
  const std::string crs = root["crs"].as<std::string>();
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
    return Error{file + ": crs: GDAL does not know '" + crs + "'"};
  if (!srs.IsProjected()) return Error{file + ": crs: '" + crs + "' is not a projected CRS"};
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  const std::string crs_wkt = wkt ? wkt : "";
  CPLFree(wkt);
  const YAML::Node points = root["points"];
  if (!points || !points.IsSequence()) return Error{file + ": points: missing (a list of GCPs)"};
  std::vector<GroundControlPoint> gcps;
  for (size_t i = 0; i < points.size(); ++i) {
    const std::string where = file + ": points[" + std::to_string(i) + "]";
    GroundControlPoint g;
    g.name = points[i]["name"] ? points[i]["name"].as<std::string>() : std::to_string(i);
    const auto station = ReadTriple(points[i]["station"], where + ".station");
    if (!station) return Error{station.error()};
    const auto world = ReadTriple(points[i]["world"], where + ".world");
    if (!world) return Error{world.error()};
    g.station_m = *station, g.world_m = *world;
    gcps.push_back(g);
  }
  Result<Georeference> fit = FitGeoreference(gcps, crs_wkt);
  if (!fit) return Error{file + ": points: " + fit.error()};
  return fit;
}

}  // namespace ts
