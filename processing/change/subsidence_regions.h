#pragma once
// The connected areas of significant lowering of a DEM of difference, grown into their rims:
// statistics per region and outlines traced along cell edges by GDAL's polygonizer.
#include <vector>

#include "processing/change/dem_of_difference.h"

namespace ts {

// Significant cores of at least min_region_area_m2, each grown (4-neighbours) into the cells
// lowered by at least region_grow_t sigma, then ring by ring into its basin while a ring is
// lowered as a whole; largest volume first, numbered from 1.
std::vector<SubsidenceRegion> FindSubsidenceRegions(const ChangeResult& change,
                                                    const ChangeOptions& options);

}  // namespace ts
