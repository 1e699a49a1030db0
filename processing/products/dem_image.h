#pragma once
// dem.png: the DEM as a coloured hillshade for the operator: heights in colour (low blue to
// high red, nodata grey), shaded by a sun in the north-west at 45 degrees, the station marked,
// a scale bar and the height range written under it.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "processing/io/raster.h"
#include "processing/products/map_drawing.h"

namespace ts {

struct DemImageOptions {
  int pixels_per_cell = 8;
  HillshadeOptions shade;
};

// station_xy_m: where to draw the station marker, in the raster's coordinates. BGR, 8 bit.
cv::Mat RenderDemImage(const Raster& dem, const Eigen::Vector2d& station_xy_m,
                       const DemImageOptions& options = {});

}  // namespace ts
