#pragma once
// Georeferencing of a station with ground control points: a GCP is a point known both in the
// station frame L and in a projected CRS (easting, northing, height). Two or more GCPs fix a
// horizontal similarity (scale, rotation, shift; least squares from three on) and a height
// offset (their mean); L's Z is along gravity, so no tilt is estimated. Without GCPs the DEM
// stays in L.
//
// GCP file (YAML):
//   crs: EPSG:32633            # anything GDAL's SetFromUserInput accepts
//   points:
//     - {name: A, station: [x, y, z], world: [easting, northing, height]}
//     - ...
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

struct GroundControlPoint {
  std::string name;
  Eigen::Vector3d station_m = Eigen::Vector3d::Zero();  // in L
  Eigen::Vector3d world_m = Eigen::Vector3d::Zero();    // in the CRS
};

struct Georeference {
  std::string crs_wkt;
  double scale = 1.0;
  double rotation_rad = 0.0;  // world = s R(rotation) station + shift (counter-clockwise)
  Eigen::Vector2d shift_m = Eigen::Vector2d::Zero();
  double height_offset_m = 0.0;
  std::vector<double> residuals_m;  // per GCP, 3D, after the fit
  Eigen::Vector3d ToWorld(const Eigen::Vector3d& station_m) const;
};

// Needs at least two GCPs with distinct horizontal positions; errors say which.
Result<Georeference> FitGeoreference(const std::vector<GroundControlPoint>& gcps,
                                     const std::string& crs_wkt);

// Reads a GCP file (above) and fits it; errors name the file and the field.
Result<Georeference> LoadGeoreference(const std::string& gcp_file);

}  // namespace ts
