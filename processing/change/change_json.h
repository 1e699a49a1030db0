#pragma once
// change.json: what changed between two epochs (areas, volumes with errors, deepest
// subsidence, regions with outlines, warnings) and how it was decided; subsidence.geojson: the
// regions as a GeoJSON FeatureCollection for a GIS.
#include <nlohmann/json.hpp>

#include "processing/change/dem_of_difference.h"

namespace ts {

nlohmann::json ChangeToJson(const ChangeResult& change, const ChangeOptions& options);
nlohmann::json SubsidenceGeoJson(const ChangeResult& change);

}  // namespace ts
