#pragma once
// The connected areas of significant lowering of a DEM of difference: statistics per region
// and outlines traced along cell edges by GDAL's polygonizer.
#include <vector>

#include "processing/change/dem_of_difference.h"

namespace ts {

// Regions of at least min_area_m2, largest volume first, numbered from 1.
std::vector<SubsidenceRegion> FindSubsidenceRegions(const ChangeResult& change, double min_area_m2);

}  // namespace ts
