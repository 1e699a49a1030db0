#include "station/dem_input.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/options.h"
#include "processing/io/atomic_file.h"
#include "station/commands.h"

namespace ts {
namespace {

Eigen::Vector3d ReadStationMark(const std::string& station_dir) {
  const std::string report_file = station_dir + "/products/report.json";
  Result<std::string> text = ReadWholeFile(report_file);
  if (!text) throw CommandError(text.error());
  const nlohmann::json report = nlohmann::json::parse(*text, nullptr, false);
  if (report.is_discarded() || !report.contains("station_mark") ||
      !report["station_mark"].is_array() || report["station_mark"].size() != 3 ||
      !report["station_mark"][0].is_number() || !report["station_mark"][1].is_number() ||
      !report["station_mark"][2].is_number())
    throw CommandError(report_file + ": station_mark: missing or not [x, y, z]");
  Eigen::Vector3d mark;
  for (int k = 0; k < 3; ++k) mark[k] = report["station_mark"][k].get<double>();
  return mark;
}

}  // namespace

DemInput LoadDemInput(const std::string& input) {
  DemInput in;
  in.station_dir = std::filesystem::is_directory(input);
  in.dem_file = in.station_dir ? input + "/products/dem.tif" : input;
  Result<Raster> dem = ReadGeoTiff(in.dem_file);
  if (!dem)
    throw CommandError(dem.error() + (in.station_dir ? " (run `topostation process`)" : ""));
  in.dem = std::move(*dem);
  // Heights no ground on Earth has (a float's 3e38, a nodata value left undeclared) would
  // make a terrain correction of them.
  for (size_t i = 0; i < in.dem.values.size(); ++i) {
    const float h = in.dem.values[i];
    if (!Raster::IsNoData(h) && (h > kHighestGroundM || h < kLowestGroundM))
      throw CommandError(in.dem_file + ": cell (row " + std::to_string(i / in.dem.cols) +
                         ", column " + std::to_string(i % in.dem.cols) + ") holds " +
                         OptionNumberText(h) +
                         " m, a height no ground has (an undeclared nodata value?)");
  }
  std::filesystem::path std_file(in.dem_file);
  std_file.replace_filename(std_file.stem().string() + "_std" + std_file.extension().string());
  if (std::filesystem::exists(std_file)) {
    in.std_file = std_file.string();
    Result<Raster> s = ReadGeoTiff(in.std_file);
    if (!s) throw CommandError(s.error());
    if (s->cols != in.dem.cols || s->rows != in.dem.rows)
      throw CommandError(in.std_file + ": not on the grid of " + in.dem_file);
    in.std_dev = std::move(*s);
  }
  if (in.station_dir) in.station_mark = ReadStationMark(input);
  return in;
}

}  // namespace ts
