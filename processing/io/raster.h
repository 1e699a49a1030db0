#pragma once
// A north-up raster on a regular grid (a DEM, its standard deviation, a mask) and its
// GeoTIFF I/O through GDAL. Coordinates are in the station frame L (x east = X_L, y north =
// Y_L) unless crs_wkt names a projected CRS. Row 0 is the northern edge, as in GeoTIFF.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

struct Raster {
  double min_x_m = 0.0;  // western edge of column 0
  double max_y_m = 0.0;  // northern edge of row 0
  double cell_m = 1.0;   // square cells
  int cols = 0;
  int rows = 0;
  std::vector<float> values;  // row-major, rows * cols
  std::string crs_wkt;        // empty: station frame L, no CRS

  static constexpr float kNoData = -9999.0f;

  // An all-nodata raster whose cells tile [min_x, min_x + cols*cell] x [max_y - rows*cell, max_y].
  static Raster Make(double min_x_m, double max_y_m, double cell_m, int cols, int rows,
                     float fill = kNoData);
  float& at(int row, int col) { return values[static_cast<size_t>(row) * cols + col]; }
  float at(int row, int col) const { return values[static_cast<size_t>(row) * cols + col]; }
  double CellCentreX(int col) const { return min_x_m + (col + 0.5) * cell_m; }
  double CellCentreY(int row) const { return max_y_m - (row + 0.5) * cell_m; }
  static bool IsNoData(float v) { return !std::isfinite(v) || v == kNoData; }
  // The cell holding (x, y); false outside the raster.
  bool CellOf(double x_m, double y_m, int* row, int* col) const {
    *col = static_cast<int>(std::floor((x_m - min_x_m) / cell_m));
    *row = static_cast<int>(std::floor((max_y_m - y_m) / cell_m));
    return *col >= 0 && *row >= 0 && *col < cols && *row < rows;
  }
  // The value of the cell holding (x, y); NaN outside or in nodata.
  double NearestCell(double x_m, double y_m) const;
  // Bilinear interpolation between cell centres; NaN outside or next to nodata.
  double Interpolate(double x_m, double y_m) const;
  // Cubic convolution (Catmull-Rom) over the 4 x 4 cells around (x, y), which follows a
  // curved surface where bilinear cuts its chords; bilinear where one of them has no data.
  double InterpolateCubic(double x_m, double y_m) const;
  enum class Sampling { kBilinear, kNearestCell };
  // This raster sampled at the cell centres of `grid` (its geometry and CRS): bilinearly, or
  // the value of the cell each centre falls in (a mask keeps its edge there).
  // turn_deg: the grid's azimuths (clockwise from +Y, about the origin) stand this far from
  // this raster's, as a station frame's do from another's when their pan zeros differ.
  // lift_m: the grid's heights stand this far above this raster's, as a station frame's do
  // when its origin lies another height under the tilt axis.
  Raster ResampledOnto(const Raster& grid, double turn_deg = 0.0, double lift_m = 0.0,
                       Sampling sampling = Sampling::kBilinear) const;
};

// Float32 GeoTIFF, one band, nodata = Raster::kNoData, deflate-compressed; written to a
// temporary name and renamed (atomic).
Status WriteGeoTiff(const Raster& raster, const std::string& path);
// The most cells a raster read here may have: a station's DEM has 3600, a DEM of a survey
// area 10 km square at 1 m 1e8 (400 MB as float).
constexpr double kMaxRasterCells = 1e8;
// Reads band 1 of any north-up raster GDAL can open, as float. Errors name the file: more
// cells than kMaxRasterCells (checked before reading), a CRS not in metres.
Result<Raster> ReadGeoTiff(const std::string& path);

}  // namespace ts
