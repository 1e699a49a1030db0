#pragma once
// The connected areas of significant lowering of a DEM of difference, grown into their rims:
// statistics per region and outlines traced along cell edges by GDAL's polygonizer.
#include <vector>

#include "processing/change/dem_of_difference.h"

namespace ts {

// Significant cores of at least min_region_area_m2 whose deepest cell reaches
// change.region_deepest_t sigma, each grown (4-neighbours) into the cells
// lowered by at least region_grow_t sigma, then ring by ring into its basin while a ring is
// lowered as a whole; largest volume first, numbered from 1.
std::vector<SubsidenceRegion> FindSubsidenceRegions(const ChangeResult& change,
                                                    const ChangeOptions& options);

// The region whose centroid lies nearest `xy_m`, if one lies within `within_m` (e.g. the region
// found at a known bowl); null otherwise.
const SubsidenceRegion* RegionNearest(const std::vector<SubsidenceRegion>& regions,
                                      const Eigen::Vector2d& xy_m, double within_m);

}  // namespace ts
