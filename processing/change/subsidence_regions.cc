#include "processing/change/subsidence_regions.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/imgproc.hpp>

namespace ts {
namespace {

struct GdalDatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, GdalDatasetCloser>;

std::vector<Eigen::Vector2d> RingPoints(const OGRLinearRing* ring) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < ring->getNumPoints(); ++i) points.emplace_back(ring->getX(i), ring->getY(i));
  return points;
}

// Traces the outline of every labelled region (labels > 0) along cell edges; rings by label.
void TraceOutlines(const cv::Mat& labels, const Raster& grid,
                   std::map<int, SubsidenceRegion*>* by_label) {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* memory = GetGDALDriverManager()->GetDriverByName("Memory");
  if (!mem || !memory) return;  // both are built into every GDAL
  DatasetPtr raster(mem->Create("", grid.cols, grid.rows, 1, GDT_Int32, nullptr));
  DatasetPtr vector(memory->Create("", 0, 0, 0, GDT_Unknown, nullptr));
  if (!raster || !vector) return;
  double transform[6] = {grid.min_x_m, grid.cell_m, 0.0, grid.max_y_m, 0.0, -grid.cell_m};
  raster->SetGeoTransform(transform);
  GDALRasterBand* band = raster->GetRasterBand(1);
  cv::Mat data = labels.isContinuous() ? labels : labels.clone();
  if (band->RasterIO(GF_Write, 0, 0, grid.cols, grid.rows, data.ptr<int32_t>(), grid.cols,
                     grid.rows, GDT_Int32, 0, 0) != CE_None)
    return;
  OGRLayer* layer = vector->CreateLayer("regions", nullptr, wkbPolygon, nullptr);
  OGRFieldDefn field("label", OFTInteger);
  if (!layer || layer->CreateField(&field) != OGRERR_NONE) return;
  char** options = CSLSetNameValue(nullptr, "8CONNECTED", "8");
  // The band is its own mask: label 0 (no region) yields no polygon.
  const CPLErr err = GDALPolygonize(band, band, layer, 0, options, nullptr, nullptr);
  CSLDestroy(options);
  if (err != CE_None) return;
  layer->ResetReading();
  for (std::unique_ptr<OGRFeature> f(layer->GetNextFeature()); f;
       f.reset(layer->GetNextFeature())) {
    const auto it = by_label->find(f->GetFieldAsInteger(0));
    const OGRGeometry* g = f->GetGeometryRef();
    if (it == by_label->end() || !g || wkbFlatten(g->getGeometryType()) != wkbPolygon) continue;
    const OGRPolygon* polygon = g->toPolygon();
    OutlinePolygon& out = it->second->outline.emplace_back();
    out.exterior = RingPoints(polygon->getExteriorRing());
    for (int i = 0; i < polygon->getNumInteriorRings(); ++i)
      out.holes.push_back(RingPoints(polygon->getInteriorRing(i)));
  }
}

// Rings of cells around each region, for as long as a ring as a whole is lowered
// significantly (mean lowering >= t_critical x its standard error): the rim where the bowl
// fades into the noise adds up even where no cell stands out, and noise of either sign
// averages out. At most basin_reach_m beyond the grown region.
void ExtendIntoBasins(const ChangeResult& change, const ChangeOptions& o,
                      const std::vector<int>& keep, cv::Mat* labels) {
  const Raster& grid = change.dod;
  const int max_rings = static_cast<int>(std::ceil(o.basin_reach_m / grid.cell_m));
  cv::Mat valid(grid.rows, grid.cols, CV_8UC1);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) valid.at<uint8_t>(r, c) = !Raster::IsNoData(grid.at(r, c));
  for (size_t k = 1; k < keep.size(); ++k) {
    if (!keep[k]) continue;
    for (int ring = 0; ring < max_rings; ++ring) {
      const cv::Mat mine = *labels == static_cast<int>(k);
      cv::Mat grown;
      cv::dilate(mine, grown, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
      const cv::Mat candidates = grown & ~mine & (*labels == 0) & valid;
      std::vector<cv::Point> cells;
      cv::findNonZero(candidates, cells);
      if (cells.empty()) break;
      double sum = 0.0, variance = 0.0;
      for (const cv::Point& p : cells) {
        sum -= grid.at(p.y, p.x);
        variance += std::pow(change.dod_std.at(p.y, p.x), 2);
      }
      const double n = static_cast<double>(cells.size());
      if (!(sum / n >= o.t_critical * std::sqrt(variance) / n)) break;
      for (const cv::Point& p : cells) labels->at<int32_t>(p) = static_cast<int32_t>(k);
    }
  }
}

}  // namespace

std::vector<SubsidenceRegion> FindSubsidenceRegions(const ChangeResult& change,
                                                    const ChangeOptions& o) {
  const Raster& grid = change.dod;
  const double cell_area = grid.cell_m * grid.cell_m;
  cv::Mat core(grid.rows, grid.cols, CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      core.at<uint8_t>(r, c) = change.change_class.at(r, c) == kSignificantLowering;
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(core, labels, stats, centroids, 8, CV_32S);
  // Among thousands of cells, a few neighbours pass the per-cell test by chance (the cells'
  // errors are correlated, so they come in clusters): a core is listed only when its deepest
  // cell stands out of the noise of the whole compared area. Cores too small or too shallow to
  // list are not grown; their cells still count in the totals.
  std::vector<double> deepest_t(count, 0.0);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      if (const int k = labels.at<int32_t>(r, c))
        deepest_t[k] = std::max(deepest_t[k], -grid.at(r, c) / double{change.dod_std.at(r, c)});
  std::vector<int> keep(count, 0);
  for (int k = 1; k < count; ++k)
    keep[k] = stats.at<int32_t>(k, cv::CC_STAT_AREA) * cell_area >= o.min_region_area_m2 &&
                      deepest_t[k] >= change.region_deepest_t
                  ? k
                  : 0;
  std::deque<cv::Point> frontier;
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      int32_t& label = labels.at<int32_t>(r, c);
      label = keep[label];
      if (label) frontier.emplace_back(c, r);
    }
  // Hysteresis: into the 4-neighbours lowered by at least grow_t sigma (never a stricter test
  // than the cores' own).
  const double grow_t = std::min(o.region_grow_t, o.t_critical);
  while (!frontier.empty()) {
    const cv::Point p = frontier.front();
    frontier.pop_front();
    for (const cv::Point step :
         {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
      const cv::Point q = p + step;
      if (q.x < 0 || q.y < 0 || q.x >= grid.cols || q.y >= grid.rows) continue;
      int32_t& label = labels.at<int32_t>(q);
      const float dz = grid.at(q.y, q.x);
      if (label || Raster::IsNoData(dz) || !(-dz >= grow_t * change.dod_std.at(q.y, q.x))) continue;
      label = labels.at<int32_t>(p);
      frontier.push_back(q);
    }
  }
  ExtendIntoBasins(change, o, keep, &labels);
  std::vector<SubsidenceRegion> regions(std::max(0, count - 1));
  std::vector<double> weight(regions.size(), 0.0);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const int label = labels.at<int32_t>(r, c);
      if (label == 0) continue;
      SubsidenceRegion& region = regions[label - 1];
      const double depth = -grid.at(r, c), sigma = change.dod_std.at(r, c);
      const Eigen::Vector2d xy(grid.CellCentreX(c), grid.CellCentreY(r));
      region.lowering.AddCell(depth, sigma, cell_area);
      region.significant_cells += change.change_class.at(r, c) == kSignificantLowering;
      region.centroid_xy_m += depth * xy;
      weight[label - 1] += depth;
      if (depth > region.max_depth_m)
        region.max_depth_m = depth, region.max_depth_sigma_m = sigma, region.deepest_xy_m = xy;
    }
  std::vector<int> new_label(regions.size() + 1, 0);
  std::vector<SubsidenceRegion> kept;
  for (size_t i = 0; i < regions.size(); ++i) {
    SubsidenceRegion& region = regions[i];
    if (!keep[i + 1]) continue;
    region.lowering.Finish();
    region.centroid_xy_m /= weight[i];
    region.id = static_cast<int>(i + 1);  // the component's label until renumbered
    kept.push_back(region);
  }
  std::sort(kept.begin(), kept.end(), [](const SubsidenceRegion& a, const SubsidenceRegion& b) {
    return a.lowering.volume_m3 > b.lowering.volume_m3;
  });
  for (size_t i = 0; i < kept.size(); ++i) {
    new_label[kept[i].id] = static_cast<int>(i + 1);
    kept[i].id = static_cast<int>(i + 1);
  }
  labels.forEach<int32_t>([&](int32_t& label, const int*) { label = new_label[label]; });
  std::map<int, SubsidenceRegion*> by_label;
  for (SubsidenceRegion& region : kept) by_label[region.id] = &region;
  TraceOutlines(labels, grid, &by_label);
  return kept;
}

const SubsidenceRegion* RegionNearest(const std::vector<SubsidenceRegion>& regions,
                                      const Eigen::Vector2d& xy_m, double within_m) {
  const SubsidenceRegion* nearest = nullptr;
  double best = within_m;
  for (const SubsidenceRegion& r : regions)
    if (const double d = (r.centroid_xy_m - xy_m).norm(); d < best) best = d, nearest = &r;
  return nearest;
}

}  // namespace ts
