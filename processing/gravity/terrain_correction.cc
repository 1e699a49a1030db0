#include "processing/gravity/terrain_correction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "processing/gravity/prism.h"

namespace ts {

bool TerrainCorrectionOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!(far_field_ratio == 0.0 || far_field_ratio >= 5.0))
    err = "far_field_ratio must be 0 (exact everywhere) or >= 5";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

constexpr double kRingEdges[] = {0.0, 2.0, 10.0, 20.0, 30.0, 50.0};
constexpr int kRings = 6;

int RingOf(double d) {
  for (int k = 1; k < kRings; ++k)
    if (d < kRingEdges[k]) return k - 1;
  return kRings - 1;
}

// The sector of a direction (x, y), bearings clockwise from +Y, sector 0 centred on 0 deg.
int SectorOf(double x, double y) {
  const double width = 360.0 / kSectors;
  const double bearing = std::atan2(x, y) * 180.0 / M_PI + 0.5 * width;
  const int k = static_cast<int>(std::floor(bearing / width));
  return ((k % kSectors) + kSectors) % kSectors;
}

// The correction of one column between height h and the reference H over the rectangle
// [x0, x1] x [y0, y1] (relative to the sensor's horizontal position), sensor at height s
// above H.
// Beyond far_field_ratio sides from the sensor the prism is taken in its far-field form
// (vertical line masses, prism.h).
double Column(double x0, double x1, double y0, double y1, double h, double ref, double sensor_z,
              const TerrainCorrectionOptions& o) {
  if (h == ref) return 0.0;
  const double lo = std::min(h, ref) - sensor_z, hi = std::max(h, ref) - sensor_z;
  const bool far = o.far_field_ratio > 0.0 && std::hypot(0.5 * (x0 + x1), 0.5 * (y0 + y1)) >=
                                                  o.far_field_ratio * std::max(x1 - x0, y1 - y0);
  const double g =
      far ? PrismDownwardAttractionFarField({x0, y0, lo}, {x1, y1, hi}, o.density_kg_m3)
          : PrismDownwardAttraction({x0, y0, lo}, {x1, y1, hi}, o.density_kg_m3);
  return h < ref ? g : -g;  // missing mass below: as it would pull; excess: opposite
}

// The standard deviation (mGal) of a column's correction when its height is known as h +- s
// (normal). Near the reference height the correction grows with the square of the height
// difference, so its slope at h (zero at the reference) says nothing of what ground metres
// higher or lower would add; far above or below, the correction saturates. Three-point
// Gauss-Hermite (nodes 0, +-sqrt 3): exact for a quadratic correction, the slope times s
// for a linear one.
double ColumnSpread(double x0, double x1, double y0, double y1, double h, double s, double ref,
                    double sensor_z, const TerrainCorrectionOptions& o) {
  const double step = std::sqrt(3.0) * s;
  const double at = Column(x0, x1, y0, y1, h, ref, sensor_z, o);
  // Differences from the centre's, against cancellation where s is small.
  const double below = Column(x0, x1, y0, y1, h - step, ref, sensor_z, o) - at;
  const double above = Column(x0, x1, y0, y1, h + step, ref, sensor_z, o) - at;
  const double mean = (below + above) / 6.0;
  const double variance = (below * below + above * above) / 6.0 - mean * mean;
  return kMgalPerMs2 * std::sqrt(std::max(0.0, variance));
}

// A square of the refined zone: split into four while it is large against its distance from
// the station (the kernel's 1/r^2 makes the flat-top error grow as the square nears it),
// each leaf a column with the surface's height at its centre.
template <typename Sample>
double RefinedColumn(double x0, double y0, double size, int depth, double fallback,
                     const Sample& sample, double ref, double sensor_z,
                     const TerrainCorrectionOptions& o) {
  const double cx = x0 + 0.5 * size, cy = y0 + 0.5 * size;
  const double distance = std::hypot(cx, cy);
  if (size > o.refine_ratio * distance && size > o.min_subcell_m && depth < 16) {
    const double s = 0.5 * size;
    double sum = 0.0;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        sum +=
            RefinedColumn(x0 + i * s, y0 + j * s, s, depth + 1, fallback, sample, ref, sensor_z, o);
    return sum;
  }
  const double z = sample(cx, cy, fallback);
  return Column(x0, x0 + size, y0, y0 + size, z, ref, sensor_z, o);
}

}  // namespace

TerrainCorrection ComputeTerrainCorrection(const Raster& dem, const Raster* dem_std,
                                           const Eigen::Vector3d& mark,
                                           const TerrainCorrectionOptions& o,
                                           const std::vector<CellGround>* ground) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("terrain correction: " + why);
  if (ground && ground->size() != dem.values.size())
    throw std::invalid_argument("terrain correction: one ground kind per DEM cell");
  TerrainCorrection tc;
  const double ref = mark.z(), sensor_z = mark.z() + o.sensor_height_m;
  // Tie the surface to the mark: the DEM's misfit there, tapered over the refined zone.
  const double at_mark = dem.Interpolate(mark.x(), mark.y());
  tc.station_misfit_m = std::isfinite(at_mark) ? at_mark - ref : 0.0;
  auto tie = [&](double d) {
    return o.refine_radius_m > 0 ? tc.station_misfit_m * std::max(0.0, 1.0 - d / o.refine_radius_m)
                                 : 0.0;
  };
  // The tied, bilinearly interpolated surface at (x, y) relative to the mark.
  auto sample = [&](double x, double y, double fallback) {
    double z = dem.Interpolate(x + mark.x(), y + mark.y());
    if (!std::isfinite(z)) z = fallback;
    return z - tie(std::hypot(x, y));
  };
  std::vector<double> ring_sum(kRings, 0.0);
  std::vector<int> ring_cells(kRings, 0), ring_data(kRings, 0), ring_seen(kRings, 0);
  std::vector<double> ring_variance(kRings, 0.0), ring_unseen(kRings, 0.0);
  struct SectorSums {
    int cells = 0, data = 0, seen = 0;
    double variance = 0.0, unseen = 0.0;
  };
  std::vector<std::array<SectorSums, kSectors>> sector(kRings);
  double correlated = 0.0;
  const double half = 0.5 * dem.cell_m;
  for (int r = 0; r < dem.rows; ++r)
    for (int c = 0; c < dem.cols; ++c) {
      const double cx = dem.CellCentreX(c) - mark.x(), cy = dem.CellCentreY(r) - mark.y();
      const double d = std::hypot(cx, cy);
      if (o.radius_m > 0 && d > o.radius_m) continue;
      const int ring = RingOf(d);
      SectorSums& in_sector = sector[ring][SectorOf(cx, cy)];
      ++ring_cells[ring];
      ++in_sector.cells;
      const float h = dem.at(r, c);
      if (Raster::IsNoData(h)) continue;
      const CellGround kind =
          ground ? (*ground)[static_cast<size_t>(r) * dem.cols + c] : CellGround::kSeen;
      ring_data[ring] += kind != CellGround::kEstimated;
      in_sector.data += kind != CellGround::kEstimated;
      in_sector.seen += kind == CellGround::kSeen;
      ring_seen[ring] += kind == CellGround::kSeen;
      double value = 0.0;
      const bool refine = d - half * M_SQRT2 < o.refine_radius_m;
      if (refine) {
        value = RefinedColumn(cx - half, cy - half, dem.cell_m, 0, h, sample, ref, sensor_z, o);
      } else {
        value = Column(cx - half, cx + half, cy - half, cy + half, h, ref, sensor_z, o);
      }
      value *= kMgalPerMs2;
      ring_sum[ring] += value;
      tc.total_mgal += value;
      tc.quadrant_mgal[cy >= 0 ? (cx >= 0 ? 0 : 3) : (cx >= 0 ? 1 : 2)] += value;
      if (dem_std) {
        const float s = dem_std->at(r, c);
        if (!Raster::IsNoData(s) && s > 0) {
          const double spread =
              ColumnSpread(cx - half, cx + half, cy - half, cy + half, h, s, ref, sensor_z, o);
          if (kind == CellGround::kSeen) {
            ring_variance[ring] += spread * spread;
            in_sector.variance += spread * spread;
          } else {
            ring_unseen[ring] += spread;
            in_sector.unseen += spread;
          }
          correlated += spread;
        }
      }
    }
  // Unseen ground as one unknown over the whole square: its ring sums add linearly too.
  double variance = 0.0;
  for (int k = 0; k < kRings; ++k)
    variance += ring_variance[k], tc.sigma_unseen_mgal += ring_unseen[k];
  tc.sigma_mgal = std::sqrt(variance + tc.sigma_unseen_mgal * tc.sigma_unseen_mgal);
  tc.sigma_correlated_mgal = correlated;
  for (int k = 0; k < kRings; ++k) {
    RingContribution ring;
    ring.inner_m = kRingEdges[k];
    ring.outer_m = k + 1 < kRings ? kRingEdges[k + 1] : std::numeric_limits<double>::infinity();
    ring.mgal = ring_sum[k];
    ring.coverage = ring_cells[k] ? static_cast<double>(ring_data[k]) / ring_cells[k] : 0.0;
    ring.sigma_unseen_mgal = ring_unseen[k];
    ring.sigma_mgal = std::sqrt(ring_variance[k] + ring_unseen[k] * ring_unseen[k]);
    for (int j = 0; j < kSectors; ++j) {
      const SectorSums& in = sector[k][j];
      auto share = [&](int n) { return in.cells ? static_cast<double>(n) / in.cells : 0.0; };
      ring.sectors.push_back({j * 360.0 / kSectors, share(in.data), share(in.seen),
                              std::sqrt(in.variance + in.unseen * in.unseen)});
    }
    if (ring_cells[k] > 0 && ring.coverage < o.min_ring_coverage) {
      char text[160];
      std::snprintf(
          text, sizeof text,
          "ring %.0f-%s m: only %.0f %% of its cells have data; its %.4f mGal is "
          "too thin to trust",
          ring.inner_m,
          std::isinf(ring.outer_m) ? "end" : std::to_string(static_cast<int>(ring.outer_m)).c_str(),
          100 * ring.coverage, ring.mgal);
      tc.warnings.push_back(text);
    }
    tc.rings.push_back(ring);
  }
  // Rings 0-2 and 2-10 m lie within 10 m, 0-30 m within 30 m.
  auto share = [&](const std::vector<int>& counted, int rings) {
    int cells = 0, n = 0;
    for (int k = 0; k < rings; ++k) cells += ring_cells[k], n += counted[k];
    return cells > 0 ? static_cast<double>(n) / cells : 1.0;
  };
  const struct {
    const std::vector<int>& counted;
    int rings, radius;
    double minimum;
    const char* what;
  } needs[] = {{ring_data, 2, 10, o.min_coverage_10m, "has DEM data"},
               {ring_data, 4, 30, o.min_coverage_30m, "has DEM data"},
               {ring_seen, 4, 30, o.min_seen_30m, "was seen (a ground point in the cell)"}};
  for (const auto& need : needs) {
    const double got = share(need.counted, need.rings);
    if (!tc.Usable() || got >= need.minimum) continue;
    char text[200];
    std::snprintf(text, sizeof text,
                  "only %.0f %% of the ground within %d m %s (%.0f %% needed): too little to "
                  "estimate the rest from",
                  100 * got, need.radius, need.what, 100 * need.minimum);
    tc.unusable_because = text;
  }
  return tc;
}

}  // namespace ts
