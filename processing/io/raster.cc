#include "processing/io/raster.h"

#include <cpl_conv.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>

namespace ts {
namespace {

void RegisterGdalOnce() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

}  // namespace

Raster Raster::Make(double min_x_m, double max_y_m, double cell_m, int cols, int rows, float fill) {
  Raster r;
  r.min_x_m = min_x_m;
  r.max_y_m = max_y_m;
  r.cell_m = cell_m;
  r.cols = cols;
  r.rows = rows;
  r.values.assign(static_cast<size_t>(cols) * rows, fill);
  return r;
}

double Raster::NearestCell(double x_m, double y_m) const {
  int row = 0, col = 0;
  if (!CellOf(x_m, y_m, &row, &col) || IsNoData(at(row, col))) return NAN;
  return at(row, col);
}

double Raster::Interpolate(double x_m, double y_m) const {
  const double fc = (x_m - min_x_m) / cell_m - 0.5, fr = (max_y_m - y_m) / cell_m - 0.5;
  const int c0 = static_cast<int>(std::floor(fc)), r0 = static_cast<int>(std::floor(fr));
  if (c0 < 0 || r0 < 0 || c0 + 1 >= cols || r0 + 1 >= rows) {
    // On the outermost half cell, fall back to the nearest cell.
    const int c = static_cast<int>(std::lround(fc)), r = static_cast<int>(std::lround(fr));
    if (c < 0 || r < 0 || c >= cols || r >= rows || std::abs(fc - c) > 0.5 + 1e-9 ||
        std::abs(fr - r) > 0.5 + 1e-9)
      return std::nan("");
    const float v = at(r, c);
    return IsNoData(v) ? std::nan("") : v;
  }
  const double tx = fc - c0, ty = fr - r0;
  const float v00 = at(r0, c0), v01 = at(r0, c0 + 1), v10 = at(r0 + 1, c0),
              v11 = at(r0 + 1, c0 + 1);
  if (IsNoData(v00) || IsNoData(v01) || IsNoData(v10) || IsNoData(v11)) return std::nan("");
  return (1 - ty) * ((1 - tx) * v00 + tx * v01) + ty * ((1 - tx) * v10 + tx * v11);
}

namespace {
// Catmull-Rom weights of the four samples around t in [0, 1).
void CubicWeights(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2 * t2 - t);
  w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
  w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}
}  // namespace

double Raster::InterpolateCubic(double x_m, double y_m) const {
  const double fc = (x_m - min_x_m) / cell_m - 0.5, fr = (max_y_m - y_m) / cell_m - 0.5;
  const int c0 = static_cast<int>(std::floor(fc)), r0 = static_cast<int>(std::floor(fr));
  if (c0 < 1 || r0 < 1 || c0 + 2 >= cols || r0 + 2 >= rows) return Interpolate(x_m, y_m);
  double wx[4], wy[4];
  CubicWeights(fc - c0, wx);
  CubicWeights(fr - r0, wy);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const float v = at(r0 - 1 + i, c0 - 1 + j);
      if (IsNoData(v)) return Interpolate(x_m, y_m);
      sum += wy[i] * wx[j] * v;
    }
  return sum;
}

Raster Raster::ResampledOnto(const Raster& grid, double turn_deg, double lift_m,
                             Sampling sampling) const {
  Raster out = grid;
  // A grid point at azimuth a is this raster's point at azimuth a - turn: turned clockwise by
  // -turn.
  const double t = -turn_deg * M_PI / 180.0, cos_t = std::cos(t), sin_t = std::sin(t);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const double x = grid.CellCentreX(c), y = grid.CellCentreY(r);
      const double here_x = x * cos_t + y * sin_t, here_y = -x * sin_t + y * cos_t;
      const double v = sampling == Sampling::kBilinear ? Interpolate(here_x, here_y)
                                                       : NearestCell(here_x, here_y);
      out.at(r, c) = std::isfinite(v) ? static_cast<float>(v + lift_m) : kNoData;
    }
  return out;
}

Status WriteGeoTiff(const Raster& raster, const std::string& path) {
  RegisterGdalOnce();
  if (raster.cols <= 0 || raster.rows <= 0 ||
      raster.values.size() != static_cast<size_t>(raster.cols) * raster.rows)
    return Error{path + ": raster has no cells or the wrong number of values"};
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) return Error{path + ": GDAL has no GTiff driver"};
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "PREDICTOR", "3");
  options = CSLSetNameValue(options, "TILED", "YES");
  Dataset ds(driver->Create(tmp.c_str(), raster.cols, raster.rows, 1, GDT_Float32, options));
  CSLDestroy(options);
  if (!ds) return Error{path + ": cannot create GeoTIFF"};
  double transform[6] = {raster.min_x_m, raster.cell_m, 0.0, raster.max_y_m, 0.0, -raster.cell_m};
  ds->SetGeoTransform(transform);
  if (!raster.crs_wkt.empty()) ds->SetProjection(raster.crs_wkt.c_str());
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(Raster::kNoData);
  std::vector<float> data = raster.values;
  if (band->RasterIO(GF_Write, 0, 0, raster.cols, raster.rows, data.data(), raster.cols,
                     raster.rows, GDT_Float32, 0, 0) != CE_None) {
    ds.reset();
    std::filesystem::remove(tmp);
    return Error{path + ": cannot write GeoTIFF data"};
  }
  ds.reset();  // flush and close
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return Error{path + ": cannot rename into place: " + ec.message()};
  return {};
}

namespace {

// Heights and distances are metres everywhere here: a CRS in degrees or feet would be taken
// for metres without a word.
Status CheckMetricCrs(const std::string& path, const std::string& wkt) {
  if (wkt.empty()) return {};
  OGRSpatialReference srs;
  if (srs.importFromWkt(wkt.c_str()) != OGRERR_NONE)
    return Error{path + ": its coordinate reference system cannot be read"};
  if (srs.IsGeographic())
    return Error{path + ": its CRS (" + std::string(srs.GetName() ? srs.GetName() : "?") +
                 ") is geographic, in degrees; reproject it into metres (gdalwarp -t_srs with a " +
                 "projected CRS such as the UTM zone)"};
  const char* unit = nullptr;
  const double metres = srs.GetLinearUnits(&unit);
  if (std::abs(metres - 1.0) > 1e-9)
    return Error{path + ": its CRS's unit is " + std::string(unit ? unit : "?") +
                 ", not metres; reproject it (gdalwarp -t_srs)"};
  return {};
}

}  // namespace

Result<Raster> ReadGeoTiff(const std::string& path) {
  RegisterGdalOnce();
  if (!std::filesystem::is_regular_file(path)) return Error{path + ": cannot read file"};
  CPLPushErrorHandler(CPLQuietErrorHandler);
  Dataset ds(static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly)));
  CPLPopErrorHandler();
  if (!ds) return Error{path + ": not a raster GDAL can read"};
  if (ds->GetRasterCount() < 1) return Error{path + ": no raster band"};
  double t[6];
  if (ds->GetGeoTransform(t) != CE_None) return Error{path + ": no geotransform"};
  if (t[2] != 0.0 || t[4] != 0.0) return Error{path + ": rotated rasters are not supported"};
  if (!(t[1] > 0.0) || std::abs(t[1] + t[5]) > 1e-9 * t[1])
    return Error{path + ": cells must be square and north-up"};
  const double cells = static_cast<double>(ds->GetRasterXSize()) * ds->GetRasterYSize();
  if (cells > kMaxRasterCells)
    return Error{path + ": " + std::to_string(ds->GetRasterXSize()) + " x " +
                 std::to_string(ds->GetRasterYSize()) + " cells, more than the " +
                 std::to_string(static_cast<long long>(kMaxRasterCells)) +
                 " a DEM here may have; crop it to the survey (gdal_translate -projwin)"};
  Raster r = Raster::Make(t[0], t[3], t[1], ds->GetRasterXSize(), ds->GetRasterYSize());
  if (const char* wkt = ds->GetProjectionRef(); wkt) r.crs_wkt = wkt;
  if (Status metric = CheckMetricCrs(path, r.crs_wkt); !metric) return Error{metric.error()};
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (band->RasterIO(GF_Read, 0, 0, r.cols, r.rows, r.values.data(), r.cols, r.rows, GDT_Float32, 0,
                     0) != CE_None)
    return Error{path + ": cannot read raster data"};
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  for (float& v : r.values)
    if ((has_nodata && v == static_cast<float>(nodata)) || !std::isfinite(v)) v = Raster::kNoData;
  return r;
}

}  // namespace ts
