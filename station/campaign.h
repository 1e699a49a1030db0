#pragma once
// The campaign table (issue 25): one row per station of a survey, to join with the
// gravimeter's file (keyed by station and line), and a GeoPackage of the stations and their
// DEM footprints for QGIS. Read from what each station holds: station.json,
// station_fields.json (the crew's fields), products/report.json, terrain_correction.json and
// evaluation.json (when the truth or check points were given).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts {

// The station directories among `dirs`: a directory holding station.json is one; any other
// is searched one level down (the daemon's stations directory). In the order given, each
// level by name.
Result<std::vector<std::string>> FindStations(const std::vector<std::string>& dirs);

// One row: {"station", "line", "time_utc", "instrument_height_m", "lat_deg", "lon_deg",
// "height_m", "position_source" (GNSS, else GCPs: the mark of a georeferenced DEM),
// "density_g_cm3", "terrain_correction_mgal", "terrain_correction_sigma_mgal",
// "ring_A_B_mgal"..., "coverage_30m", "dem_rmse_m", "calibration", "verdict",
// "verdict_reason" (station_verdict.h), "warnings"}; null where the station does not know.
Result<nlohmann::ordered_json> CampaignRow(const std::string& station_dir);

// The rows as CSV (RFC 4180: quoted where needed; warnings joined by " | "), every column any
// row has, in the order they first appear.
std::string CampaignCsv(const std::vector<nlohmann::ordered_json>& rows);

// A GeoPackage: layer "stations" (points, EPSG:4326, from the rows' positions) with each row's
// attributes, and "dem_footprints" (polygons, EPSG:4326) of the DEMs in a projected CRS.
Status WriteCampaignGeoPackage(const std::vector<nlohmann::ordered_json>& rows,
                               const std::vector<std::string>& station_dirs,
                               const std::string& file);

}  // namespace ts
