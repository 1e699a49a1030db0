#pragma once
// A station's products in one zip to download (issue 25's history): station.json,
// station_fields.json and every file of products/, under a folder named after the station.
// Written with GDAL's zip writer (deflate) to a temporary name, then published atomically
// (processing/io/atomic_file.h).
#include <string>

#include "core/result.h"

namespace ts {

Status WriteStationArchive(const std::string& station_dir, const std::string& zip_file);

}  // namespace ts
