#include "processing/dem/kriging.h"

#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <utility>
#include <vector>

#include "processing/cloud/grid_index.h"
#include "processing/common/angles.h"

namespace ts {

bool KrigingOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!variogram.Check(&err)) err = "variogram: " + err;
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

void CheckVariances(const KrigingPoints& points, const char* where) {
  if (!points.height_variances_m2.empty() &&
      points.height_variances_m2.size() != points.positions.size())
    throw std::invalid_argument(std::string(where) + ": one height variance per point, or none");
}

struct Candidate {
  double distance;
  int index;
  int quadrant;
};

// Up to n neighbours of (x, y) within the radius, balanced over the four quadrants.
void FindNeighbours(const GridIndex& grid, const std::vector<Eigen::Vector3d>& points, double x,
                    double y, int n, double radius, std::vector<Candidate>* out) {
  out->clear();
  const int c0 = grid.ColOf(x), r0 = grid.RowOf(y);
  const int max_ring = static_cast<int>(std::ceil(radius / grid.cell_m()));
  std::vector<Candidate> candidates;
  for (int ring = 0; ring <= max_ring; ++ring) {
    for (int r = r0 - ring; r <= r0 + ring; ++r)
      for (int c = c0 - ring; c <= c0 + ring; ++c) {
        if (std::max(std::abs(r - r0), std::abs(c - c0)) != ring || !grid.Inside(c, r)) continue;
        for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i) {
          const double dx = points[*i].x() - x, dy = points[*i].y() - y;
          const double d2 = dx * dx + dy * dy;  // hypot's overflow guard costs here
          if (d2 <= radius * radius)
            candidates.push_back({std::sqrt(d2), *i, (dx >= 0) + 2 * (dy >= 0)});
        }
      }
    // Every point within `ring` cells is in; enough of them that close: stop.
    const double covered = ring * grid.cell_m();
    const auto close = std::count_if(candidates.begin(), candidates.end(),
                                     [&](const Candidate& k) { return k.distance <= covered; });
    if (close >= 4 * n) break;
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
  int per_quadrant[4] = {0, 0, 0, 0};
  std::vector<Candidate> rest;
  for (const Candidate& k : candidates) {
    if (per_quadrant[k.quadrant] < (n + 3) / 4 && static_cast<int>(out->size()) < n) {
      out->push_back(k);
      ++per_quadrant[k.quadrant];
    } else {
      rest.push_back(k);
    }
  }
  for (const Candidate& k : rest)  // quadrants short of points: fill from the others
    if (static_cast<int>(out->size()) < n) out->push_back(k);
}

// Fewer neighbours than this: ordinary kriging (a local linear drift needs points to spare).
constexpr int kMinDriftPoints = 6;

// Whether (x, y) lies beyond the edge of its neighbours (at least kMinDriftPoints of them):
// all within a half-plane through it (the largest angular gap between them, seen from it,
// exceeds 180 degrees).
bool BeyondTheEdge(const std::vector<Eigen::Vector3d>& points, const std::vector<Candidate>& near,
                   double x, double y) {
  std::vector<double> angles;
  for (const Candidate& k : near)
    angles.push_back(std::atan2(points[k.index].y() - y, points[k.index].x() - x));
  return LargestAngularGap(std::move(angles)) > M_PI;
}

// The points' heights less the least-squares plane through them all.
std::vector<Eigen::Vector3d> ResidualsFromPlane(std::vector<Eigen::Vector3d> points) {
  if (points.size() < 3) return points;
  Eigen::MatrixXd a(points.size(), 3);
  Eigen::VectorXd z(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    a.row(i) << 1.0, points[i].x(), points[i].y(), z[i] = points[i].z();
  const Eigen::Vector3d plane = a.colPivHouseholderQr().solve(z);
  if (!plane.allFinite()) return points;  // collinear points: no plane to take out
  for (Eigen::Vector3d& p : points) p.z() -= plane[0] + plane[1] * p.x() + plane[2] * p.y();
  return points;
}

}  // namespace

std::vector<Eigen::Vector3d> KrigingPoints::All() const {
  std::vector<Eigen::Vector3d> all = positions;
  all.insert(all.end(), surveyed.begin(), surveyed.end());
  return all;
}

KrigingPoints ThinPoints(const KrigingPoints& points, double cell_m) {
  if (!(cell_m > 0.0)) return points;
  const bool weighted = !points.height_variances_m2.empty();
  const GridIndex grid(points.positions, cell_m);
  KrigingPoints thinned;
  thinned.surveyed = points.surveyed;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      const int count = grid.Count(c, r);
      if (count == 0) continue;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      double variance_sum = 0.0;
      for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i) {
        sum += points.positions[*i];
        if (weighted) variance_sum += points.height_variances_m2[*i];
      }
      thinned.positions.push_back(sum / count);
      if (weighted) thinned.height_variances_m2.push_back(variance_sum / count / count);
    }
  return thinned;
}

void KrigeOnto(const KrigingPoints& kriging_points, const VariogramModel& model,
               const KrigingOptions& o, Raster* dem, Raster* std_dev) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("KrigingOptions: " + why);
  CheckVariances(kriging_points, "KrigeOnto");
  const std::vector<Eigen::Vector3d> points = kriging_points.All();
  // Each point's nugget: its own variance where it is larger than the fitted one; none for
  // the surveyed points.
  std::vector<double> nugget(points.size(), 0.0);
  for (size_t i = 0; i < kriging_points.positions.size(); ++i)
    nugget[i] = kriging_points.height_variances_m2.empty()
                    ? model.nugget
                    : std::max(model.nugget, kriging_points.height_variances_m2[i]);
  *std_dev = *dem;
  std::fill(dem->values.begin(), dem->values.end(), Raster::kNoData);
  std::fill(std_dev->values.begin(), std_dev->values.end(), Raster::kNoData);
  if (points.empty()) return;
  const GridIndex grid(points, std::max(0.5, o.max_distance_m / 2));
  cv::parallel_for_(cv::Range(0, dem->rows), [&](const cv::Range& rows) {
    std::vector<Candidate> near;
    for (int row = rows.start; row < rows.end; ++row)
      for (int col = 0; col < dem->cols; ++col) {
        const double x = dem->CellCentreX(col), y = dem->CellCentreY(row);
        FindNeighbours(grid, points, x, y, o.neighbours, o.search_radius_m, &near);
        if (near.empty() || near.front().distance > o.max_distance_m) continue;
        // Beyond the edge of the data the drift is extrapolated: from more neighbours, a slope
        // of the region rather than of the edge's last metre.
        if (o.linear_drift && static_cast<int>(near.size()) >= kMinDriftPoints &&
            o.extrapolation_neighbours > o.neighbours && BeyondTheEdge(points, near, x, y))
          FindNeighbours(grid, points, x, y, o.extrapolation_neighbours, o.search_radius_m, &near);
        const int n = static_cast<int>(near.size());
        // Local linear drift (universal kriging) where the points allow: a gap on a slope is
        // bridged along the slope, not levelled towards the neighbours' mean.
        const int drift = (o.linear_drift && n >= kMinDriftPoints) ? 3 : 1;
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + drift, n + drift);
        Eigen::VectorXd b = Eigen::VectorXd::Zero(n + drift);
        for (int i = 0; i < n; ++i) {
          const Eigen::Vector3d& p = points[near[i].index];
          a(i, i) = model.partial_sill + nugget[near[i].index];
          for (int j = i + 1; j < n; ++j) {
            const Eigen::Vector3d& q = points[near[j].index];
            a(i, j) = a(j, i) = model.SignalCovariance(std::hypot(p.x() - q.x(), p.y() - q.y()));
          }
          a(i, n) = a(n, i) = 1.0;
          if (drift == 3) {
            a(i, n + 1) = a(n + 1, i) = p.x() - x;
            a(i, n + 2) = a(n + 2, i) = p.y() - y;
          }
          b[i] = model.SignalCovariance(near[i].distance);
        }
        b[n] = 1.0;
        const Eigen::VectorXd solution = a.fullPivLu().solve(b);
        if (!solution.allFinite()) continue;
        double z = 0.0;
        for (int i = 0; i < n; ++i) z += solution[i] * points[near[i].index].z();
        const double variance =
            std::max(0.0, model.partial_sill - solution.head(n).dot(b.head(n)) - solution[n]);
        dem->at(row, col) = static_cast<float>(z);
        std_dev->at(row, col) = static_cast<float>(std::sqrt(variance));
      }
  });
}

KrigingResult KrigeDem(const KrigingPoints& points, const Raster& grid, const KrigingOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("KrigingOptions: " + why);
  CheckVariances(points, "KrigeDem");  // before thinning indexes them
  KrigingResult result;
  const KrigingPoints thinned = ThinPoints(points, o.thin_cell_m);
  result.points_used = thinned.positions.size();
  // With a drift, the variogram is the residual's (universal kriging): the trend's own rise,
  // a slope's s^2 h^2 / 2, is what the drift takes out; left in, it overstates the std.
  result.experimental = ComputeExperimentalVariogram(
      o.linear_drift ? ResidualsFromPlane(thinned.positions) : thinned.positions, o.variogram);
  result.model = FitVariogram(result.experimental);
  result.dem = grid;
  KrigeOnto(thinned, result.model, o, &result.dem, &result.std);
  return result;
}

}  // namespace ts
