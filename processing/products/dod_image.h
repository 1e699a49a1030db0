#pragma once
// dod.png: the DEM of difference for the deformation user. Significant lowering in red,
// raising in blue (diverging, full colour at the largest significant change), change below
// the level of detection as a grey hillshade of the later DEM, no data white; subsidence
// regions outlined and numbered, the station marked, a scale bar and the colour scale.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

#include "processing/change/dem_of_difference.h"

namespace ts {

// shade_dem: a DEM on the DoD's grid for the grey background (e.g. the later epoch).
cv::Mat RenderDodImage(const ChangeResult& change, const Raster* shade_dem,
                       const std::optional<Eigen::Vector2d>& station_xy_m, int pixels_per_cell = 8);

}  // namespace ts
