#pragma once
// What the map images (dem.png, dod.png) share: a hillshade of a raster, the station marker,
// the scale bar. Images are BGR, `pixels_per_cell` pixels per raster cell, north up.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>

#include "processing/io/raster.h"

namespace ts {

struct HillshadeOptions {
  double sun_azimuth_deg = 315.0;  // clockwise from north
  double sun_elevation_deg = 45.0;
  double vertical_exaggeration = 2.0;
};

// Lambertian shade per cell in [0, 1] (Horn's 3x3 gradient, edges and nodata neighbours
// replaced by the cell itself); CV_32FC1 of rows x cols, NaN where the raster has no data.
cv::Mat ComputeHillshade(const Raster& dem, const HillshadeOptions& options = {});

// A black-ringed white triangle at station_xy_m (the raster's coordinates).
void DrawStationMarker(cv::Mat* image, const Raster& grid, int pixels_per_cell,
                       const Eigen::Vector2d& station_xy_m);

// A scale bar of 10 m (or a fifth of the width) at row y0 with `text` after it.
void DrawScaleBarAndText(cv::Mat* image, const Raster& grid, int pixels_per_cell, int y0,
                         const std::string& text);

}  // namespace ts
