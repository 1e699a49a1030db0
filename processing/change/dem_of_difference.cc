#include "processing/change/dem_of_difference.h"

#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "processing/change/subsidence_regions.h"
#include "processing/common/family_wise.h"
#include "processing/common/median.h"

namespace ts {
namespace {

bool SameGrid(const Raster& a, const Raster& b) {
  const double tol = 1e-6 * a.cell_m;
  return a.cols == b.cols && a.rows == b.rows && std::abs(a.cell_m - b.cell_m) < tol &&
         std::abs(a.min_x_m - b.min_x_m) < tol && std::abs(a.max_y_m - b.max_y_m) < tol;
}

bool SameCrs(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a == b) return true;
  OGRSpatialReference sa, sb;
  if (sa.importFromWkt(a.c_str()) != OGRERR_NONE || sb.importFromWkt(b.c_str()) != OGRERR_NONE)
    return false;
  return sa.IsSame(&sb);
}

std::string CrsName(const std::string& wkt) {
  if (wkt.empty()) return "the station frame (no CRS)";
  OGRSpatialReference s;
  if (s.importFromWkt(wkt.c_str()) != OGRERR_NONE || !s.GetName()) return "a CRS";
  return std::string("CRS '") + s.GetName() + "'";
}

bool ExtentsOverlap(const Raster& a, const Raster& b) {
  const double a_max_x = a.min_x_m + a.cols * a.cell_m, a_min_y = a.max_y_m - a.rows * a.cell_m;
  const double b_max_x = b.min_x_m + b.cols * b.cell_m, b_min_y = b.max_y_m - b.rows * b.cell_m;
  return a.min_x_m < b_max_x && b.min_x_m < a_max_x && a_min_y < b.max_y_m && b_min_y < a.max_y_m;
}

Status CheckStdGrid(const DemEpoch& e) {
  if (e.std_dev && !SameGrid(e.dem, *e.std_dev))
    return Error{e.name + ": its standard deviation grid is not on the DEM's grid"};
  return {};
}

}  // namespace

void ChangeVolume::AddCell(double amount_m, double sigma_m, double cell_area_m2) {
  ++cells;
  area_m2 += cell_area_m2;
  volume_m3 += amount_m * cell_area_m2;
  sigma_m3 += sigma_m * cell_area_m2 * sigma_m * cell_area_m2;
  sigma_correlated_m3 += sigma_m * cell_area_m2;
}

void ChangeVolume::Finish() { sigma_m3 = std::sqrt(sigma_m3); }

bool ChangeOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

namespace {

Result<ChangeResult> CompareEpochs(const DemEpoch& before, const DemEpoch& after,
                                   const ChangeOptions& o) {
  if (before.dem.cols <= 0 || before.dem.rows <= 0) return Error{before.name + ": empty DEM"};
  if (after.dem.cols <= 0 || after.dem.rows <= 0) return Error{after.name + ": empty DEM"};
  if (Status s = CheckStdGrid(before); !s) return Error{s.error()};
  if (Status s = CheckStdGrid(after); !s) return Error{s.error()};
  if (!SameCrs(before.dem.crs_wkt, after.dem.crs_wkt))
    return Error{after.name + ": in " + CrsName(after.dem.crs_wkt) + ", but " + before.name +
                 " is in " + CrsName(before.dem.crs_wkt) + "; bring both into one frame first"};
  if (!ExtentsOverlap(before.dem, after.dem))
    return Error{after.name + ": does not overlap " + before.name};
  const bool have_std = before.std_dev && after.std_dev;
  if (!have_std && o.lod_m <= 0.0)
    return Error{(before.std_dev ? after.name : before.name) +
                 ": no standard deviation grid (X_std.tif beside X.tif): give a fixed level "
                 "of detection instead"};

  ChangeResult out;
  Raster after_dem = after.dem, after_std;
  if (after.std_dev) after_std = *after.std_dev;
  if (!SameGrid(before.dem, after.dem)) {
    out.after_resampled = true;
    after_dem = after.dem.ResampledOnto(before.dem);
    if (after.std_dev) after_std = after.std_dev->ResampledOnto(before.dem);
  }
  out.sigma_from_lod = !have_std;
  out.dod = Raster::Make(before.dem.min_x_m, before.dem.max_y_m, before.dem.cell_m, before.dem.cols,
                         before.dem.rows);
  out.dod.crs_wkt = before.dem.crs_wkt;
  out.dod_std = out.dod;
  out.change_class = out.dod;

  const double cell_area = before.dem.cell_m * before.dem.cell_m;
  int before_cells = 0, after_cells = 0;
  std::vector<float> stable, stable_lod;  // dz and detection level of the unchanged cells
  for (int r = 0; r < out.dod.rows; ++r)
    for (int c = 0; c < out.dod.cols; ++c) {
      const float z0 = before.dem.at(r, c), z1 = after_dem.at(r, c);
      before_cells += !Raster::IsNoData(z0);
      after_cells += !Raster::IsNoData(z1);
      if (Raster::IsNoData(z0) || Raster::IsNoData(z1)) continue;
      double sigma = o.lod_m / o.t_critical;
      if (have_std) {
        const float s0 = before.std_dev->at(r, c), s1 = after_std.at(r, c);
        if (Raster::IsNoData(s0) || Raster::IsNoData(s1)) continue;
        sigma = std::hypot(static_cast<double>(s0), static_cast<double>(s1));
      }
      const double dz = static_cast<double>(z1) - z0;
      const bool significant =
          o.lod_m > 0.0 ? std::abs(dz) >= o.lod_m : std::abs(dz) >= o.t_critical * sigma;
      const float cls = !significant ? kBelowDetection
                        : dz < 0.0   ? kSignificantLowering
                                     : kSignificantRaising;
      out.dod.at(r, c) = static_cast<float>(dz);
      out.dod_std.at(r, c) = static_cast<float>(sigma);
      out.change_class.at(r, c) = cls;
      ++out.cells_compared;
      if (cls == kBelowDetection) {
        stable.push_back(static_cast<float>(dz));
        stable_lod.push_back(static_cast<float>(o.lod_m > 0.0 ? o.lod_m : o.t_critical * sigma));
        continue;
      }
      (cls < 0 ? out.lowering : out.raising).AddCell(std::abs(dz), sigma, cell_area);
      out.net_volume_m3 += dz * cell_area;
      out.net_sigma_m3 += sigma * cell_area * sigma * cell_area;
      if (cls < 0 && (!out.max_subsidence_m || -dz > *out.max_subsidence_m)) {
        out.max_subsidence_m = -dz;
        out.max_subsidence_sigma_m = sigma;
        out.max_subsidence_xy_m = {out.dod.CellCentreX(c), out.dod.CellCentreY(r)};
      }
    }
  if (out.cells_compared == 0)
    return Error{after.name + ": no cell has data in both epochs (and in both std grids)"};
  out.lowering.Finish();
  out.raising.Finish();
  out.net_sigma_m3 = std::sqrt(out.net_sigma_m3);
  out.area_compared_m2 = out.cells_compared * cell_area;
  out.compared_fraction_before = static_cast<double>(out.cells_compared) / before_cells;
  out.compared_fraction_after = static_cast<double>(out.cells_compared) / after_cells;
  out.stable_median_m = Median(std::move(stable));
  out.region_deepest_t = FamilyWiseCriticalValue(out.cells_compared, TwoSidedTail(o.t_critical));
  out.regions = FindSubsidenceRegions(out, o);

  char text[240];
  for (const auto& [fraction, name] : {std::pair{out.compared_fraction_before, &before.name},
                                       std::pair{out.compared_fraction_after, &after.name}})
    if (fraction < 0.5) {
      std::snprintf(text, sizeof text,
                    "only %.0f %% of the cells with data in %s are compared (the rest has no "
                    "data in the other epoch)",
                    100.0 * fraction, name->c_str());
      out.warnings.push_back(text);
    }
  // Unchanged ground should difference to zero; a median offset beyond half the typical
  // detection level says the epochs' heights are not tied to one datum.
  if (!stable_lod.empty() && std::abs(out.stable_median_m) > 0.5 * Median(stable_lod)) {
    std::snprintf(text, sizeof text,
                  "the unchanged ground differs by a median %+.3f m between the epochs: their "
                  "heights are not on one datum (station height, GCPs?)",
                  out.stable_median_m);
    out.warnings.push_back(text);
  }
  if (out.sigma_from_lod)
    out.warnings.push_back(
        "no standard deviation grids: cell sigma taken as the level of detection / t_critical");
  return out;
}

}  // namespace

Result<ChangeResult> ComputeDemOfDifference(const DemEpoch& before, const DemEpoch& after,
                                            const ChangeOptions& o) {
  std::string why;
  if (!o.Check(&why)) return Error{"change detection: " + why};
  Result<ChangeResult> first = CompareEpochs(before, after, o);
  if (!first || !o.remove_stable_offset) return first;
  // Level the later epoch on the unchanged ground: first by the median dz of all cells (a
  // change is a minority of them, and an offset beyond the LoD leaves no cell "unchanged"),
  // then by the median of the cells the levelled comparison finds unchanged.
  std::vector<float> all;
  for (float dz : first->dod.values)
    if (!Raster::IsNoData(dz)) all.push_back(dz);
  DemEpoch levelled = after;
  double offset = Median(all);
  Result<ChangeResult> result = Error{""};
  for (int pass = 0; pass < 2; ++pass) {
    levelled.dem = after.dem;
    for (float& z : levelled.dem.values)
      if (!Raster::IsNoData(z)) z -= static_cast<float>(offset);
    result = CompareEpochs(before, levelled, o);
    if (!result) return result;
    offset += result->stable_median_m;
  }
  result->offset_removed_m = offset - result->stable_median_m;
  char text[160];
  std::snprintf(text, sizeof text,
                "the later epoch was lowered by %+.3f m, the median dz of the unchanged ground",
                result->offset_removed_m);
  result->warnings.push_back(text);
  return result;
}

}  // namespace ts
