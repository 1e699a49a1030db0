#include "processing/dem/kriging.h"

#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <optional>
#include <random>
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
  if (!points.matches.empty() && points.matches.size() != points.positions.size())
    throw std::invalid_argument(std::string(where) + ": one match per point, or none");
}

struct Candidate {
  double distance;
  int index;
  int quadrant;
};

// One thread's neighbour searches: the buffers grow once, not at every cell.
struct NeighbourSearch {
  std::vector<Candidate> near;  // the result
  std::vector<Candidate> candidates, rest;
};

// Up to n neighbours of (x, y) within the radius, balanced over the four quadrants, into
// search->near.
void FindNeighbours(const GridIndex& grid, const std::vector<Eigen::Vector3d>& points, double x,
                    double y, int n, double radius, NeighbourSearch* search, int excluded = -1) {
  std::vector<Candidate>& out = search->near;
  std::vector<Candidate>& candidates = search->candidates;
  out.clear();
  candidates.clear();
  const int c0 = grid.ColOf(x), r0 = grid.RowOf(y);
  const int max_ring = static_cast<int>(std::ceil(radius / grid.cell_m()));
  for (int ring = 0; ring <= max_ring; ++ring) {
    for (int r = r0 - ring; r <= r0 + ring; ++r)
      for (int c = c0 - ring; c <= c0 + ring; ++c) {
        if (std::max(std::abs(r - r0), std::abs(c - c0)) != ring || !grid.Inside(c, r)) continue;
        for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i) {
          if (*i == excluded) continue;
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
  // The choice below reads the candidates nearest first. Where the nearest 4n hold every
  // quadrant's share it takes n of them and reads no further, and only they need sorting (a
  // tenth of the candidates or fewer); where points are thin on one side, all are sorted.
  const auto nearer = [](const Candidate& a, const Candidate& b) {
    return a.distance < b.distance;
  };
  const int share = (n + 3) / 4;
  const auto prefix = candidates.begin() + std::min<size_t>(candidates.size(), 4 * n);
  std::partial_sort(candidates.begin(), prefix, candidates.end(), nearer);
  int in_prefix[4] = {0, 0, 0, 0};
  for (auto k = candidates.begin(); k != prefix; ++k) ++in_prefix[k->quadrant];
  if (*std::min_element(in_prefix, in_prefix + 4) < share)
    std::sort(prefix, candidates.end(), nearer);
  int per_quadrant[4] = {0, 0, 0, 0};
  std::vector<Candidate>& rest = search->rest;
  rest.clear();
  for (const Candidate& k : candidates) {
    if (per_quadrant[k.quadrant] < share && static_cast<int>(out.size()) < n) {
      out.push_back(k);
      ++per_quadrant[k.quadrant];
    } else {
      rest.push_back(k);
    }
  }
  for (const Candidate& k : rest)  // quadrants short of points: fill from the others
    if (static_cast<int>(out.size()) < n) out.push_back(k);
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

namespace {

// The mean window of the members of [begin, end) from the pair most of them came from.
PointMatch MeanMatch(const std::vector<PointMatch>& matches, const int* begin, const int* end) {
  int most_pair = -1, most = 0;
  for (const int* i = begin; i != end; ++i) {
    const int pair = matches[*i].pair;
    const int count =
        static_cast<int>(std::count_if(begin, end, [&](int k) { return matches[k].pair == pair; }));
    if (count > most) most = count, most_pair = pair;
  }
  PointMatch mean{most_pair, {}};
  for (const int* i = begin; i != end; ++i) {
    if (matches[*i].pair != most_pair) continue;
    mean.window.centre_px += matches[*i].window.centre_px / most;
    mean.window.half_size_px += matches[*i].window.half_size_px / most;
  }
  return mean;
}

// The variance of the mean height of the points [begin, end): their errors correlate as their
// windows share noise; without their matches, all as one error (the mean of their variances).
double MeanVariance(const KrigingPoints& points, const int* begin, const int* end) {
  const std::vector<double>& v = points.height_variances_m2;
  const double count = static_cast<double>(end - begin);
  double sum = 0.0;
  if (points.matches.empty()) {
    for (const int* i = begin; i != end; ++i) sum += v[*i];
    return sum / count;
  }
  for (const int* i = begin; i != end; ++i) {
    sum += v[*i];
    for (const int* j = i + 1; j != end; ++j)
      sum += 2.0 * SharedNoiseCovariance(points.matches[*i], v[*i], points.matches[*j], v[*j]);
  }
  return sum / (count * count);
}

}  // namespace

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
      for (const int* i = grid.begin(c, r); i != grid.end(c, r); ++i) sum += points.positions[*i];
      thinned.positions.push_back(sum / count);
      if (weighted)
        thinned.height_variances_m2.push_back(
            MeanVariance(points, grid.begin(c, r), grid.end(c, r)));
      if (!points.matches.empty())
        thinned.matches.push_back(MeanMatch(points.matches, grid.begin(c, r), grid.end(c, r)));
    }
  return thinned;
}

namespace {

// Each point's nugget: its own variance where it is larger than the fitted one; none for the
// surveyed points (listed after the matched ones, as KrigingPoints::All() has them).
std::vector<double> NuggetsOf(const KrigingPoints& points, const VariogramModel& model) {
  std::vector<double> nugget(points.positions.size() + points.surveyed.size(), 0.0);
  for (size_t i = 0; i < points.positions.size(); ++i)
    nugget[i] = points.height_variances_m2.empty()
                    ? model.nugget
                    : std::max(model.nugget, points.height_variances_m2[i]);
  return nugget;
}

// Each point's own noise variance: the measured one (from the intersection; none for the
// surveyed points) where the points carry one, else its nugget.
std::vector<double> OwnNoiseVariances(const KrigingPoints& points,
                                      const std::vector<double>& nugget) {
  if (points.height_variances_m2.empty()) return nugget;
  std::vector<double> v(points.positions.size() + points.surveyed.size(), 0.0);
  std::copy(points.height_variances_m2.begin(), points.height_variances_m2.end(), v.begin());
  return v;
}

struct Estimate {
  double z = 0.0, variance = 0.0;
  // The part of variance that is the points' own noise (OwnNoiseVariances).
  double noise_variance = 0.0;
  // With a held-out point at (x, y): the covariance of the estimate's error with its noise, the
  // weighted share of image noise it has with the neighbours.
  double held_out_covariance = 0.0;
};

// A point held out of kriging and predicted from the rest.
struct HeldOut {
  const PointMatch* match = nullptr;
  double nugget = 0.0;
  int index = -1;  // its index among the points kriged from, when it is one of them
};

// What the kriging system, whose nuggets are independent, leaves out of its estimate's variance:
// the weighted covariances of the neighbours' errors that share image noise,
// sum over i != j of w_i w_j rho_ij sqrt(nugget_i nugget_j).
double SharedNoiseVariance(const std::vector<Candidate>& near, const Eigen::VectorXd& weights,
                           const std::vector<double>& nugget,
                           const std::vector<PointMatch>& matches) {
  double variance = 0.0;
  for (size_t i = 0; i < near.size(); ++i)
    for (size_t j = i + 1; j < near.size(); ++j) {
      const int a = near[i].index, b = near[j].index;
      variance += 2.0 * weights[i] * weights[j] *
                  SharedNoiseCovariance(matches[a], nugget[a], matches[b], nugget[b]);
    }
  return variance;
}

// The matches of KrigingPoints::All(): none for the surveyed points; empty if the points have
// none.
std::vector<PointMatch> MatchesOfAll(const KrigingPoints& points) {
  if (points.matches.empty()) return {};
  std::vector<PointMatch> all = points.matches;
  all.resize(points.positions.size() + points.surveyed.size());
  return all;
}

// The kriged surface at (x, y), or none where the nearest point is beyond max_distance_m.
std::optional<Estimate> KrigeAt(const GridIndex& grid, const std::vector<Eigen::Vector3d>& points,
                                const std::vector<double>& nugget,
                                const std::vector<double>& own_noise,
                                const std::vector<PointMatch>& matches, const VariogramModel& model,
                                const KrigingOptions& o, double x, double y,
                                NeighbourSearch* search, HeldOut held_out = {}) {
  const std::vector<Candidate>& near = search->near;
  FindNeighbours(grid, points, x, y, o.neighbours, o.search_radius_m, search, held_out.index);
  if (near.empty() || near.front().distance > o.max_distance_m) return std::nullopt;
  // Beyond the edge of the data the drift is extrapolated: from more neighbours, a slope of the
  // region rather than of the edge's last metre.
  if (o.linear_drift && static_cast<int>(near.size()) >= kMinDriftPoints &&
      o.extrapolation_neighbours > o.neighbours && BeyondTheEdge(points, near, x, y))
    FindNeighbours(grid, points, x, y, o.extrapolation_neighbours, o.search_radius_m, search,
                   held_out.index);
  const int n = static_cast<int>(near.size());
  // Local linear drift (universal kriging) where the points allow: a gap on a slope is bridged
  // along the slope, not levelled towards the neighbours' mean.
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
  // Partial pivoting solves a well-posed system exactly, and faster; points in a line leave the
  // drift undetermined, and there full pivoting decides, as it always did.
  Eigen::VectorXd solution = a.partialPivLu().solve(b);
  if (!solution.allFinite() || (a * solution - b).norm() > 1e-9 * b.norm())
    solution = a.fullPivLu().solve(b);
  if (!solution.allFinite()) return std::nullopt;
  Estimate e;
  for (int i = 0; i < n; ++i) e.z += solution[i] * points[near[i].index].z();
  e.variance = model.partial_sill - solution.head(n).dot(b.head(n)) - solution[n];
  for (int i = 0; i < n; ++i)
    e.noise_variance += solution[i] * solution[i] * own_noise[near[i].index];
  if (!matches.empty()) {
    const double shared = SharedNoiseVariance(near, solution, nugget, matches);
    e.variance += shared;
    // With the floors' sizes: the held-out test cannot see what neighbours share (below).
    e.noise_variance += shared;
  }
  e.variance = std::max(0.0, e.variance);
  e.noise_variance = std::clamp(e.noise_variance, 0.0, e.variance);
  if (held_out.match && !matches.empty())
    for (int i = 0; i < n; ++i)
      e.held_out_covariance +=
          solution[i] * SharedNoiseCovariance(*held_out.match, held_out.nugget,
                                              matches[near[i].index], nugget[near[i].index]);
  return e;
}

}  // namespace

namespace {

// Kriging onto `dem`'s cells; noise_variance (or none) gets each cell's share of its variance
// that is the points' own noise.
void KrigeCells(const KrigingPoints& kriging_points, const VariogramModel& model,
                const KrigingOptions& o, Raster* dem, Raster* std_dev,
                std::vector<double>* noise_variance) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("KrigingOptions: " + why);
  CheckVariances(kriging_points, "KrigeOnto");
  const std::vector<Eigen::Vector3d> points = kriging_points.All();
  const std::vector<double> nugget = NuggetsOf(kriging_points, model);
  const std::vector<PointMatch> matches = MatchesOfAll(kriging_points);
  *std_dev = *dem;
  std::fill(dem->values.begin(), dem->values.end(), Raster::kNoData);
  std::fill(std_dev->values.begin(), std_dev->values.end(), Raster::kNoData);
  if (noise_variance) noise_variance->assign(dem->values.size(), 0.0);
  if (points.empty()) return;
  const GridIndex grid(points, std::max(0.5, o.max_distance_m / 2));
  const std::vector<double> own_noise = OwnNoiseVariances(kriging_points, nugget);
  cv::parallel_for_(cv::Range(0, dem->rows), [&](const cv::Range& rows) {
    NeighbourSearch search;
    for (int row = rows.start; row < rows.end; ++row)
      for (int col = 0; col < dem->cols; ++col) {
        const std::optional<Estimate> e =
            KrigeAt(grid, points, nugget, own_noise, matches, model, o, dem->CellCentreX(col),
                    dem->CellCentreY(row), &search);
        if (!e) continue;
        dem->at(row, col) = static_cast<float>(e->z);
        std_dev->at(row, col) = static_cast<float>(std::sqrt(e->variance));
        if (noise_variance)
          (*noise_variance)[static_cast<size_t>(row) * dem->cols + col] = e->noise_variance;
      }
  });
}

// A matched point predicted from all the others: its squared error, and the parts of its
// predicted variance that are the surface's (which the variogram's sill scales) and noise's.
struct HeldOutTest {
  double x = 0.0, y = 0.0;
  double error2 = 0.0, signal_variance = 0.0, noise_variance = 0.0;
};

// Per cell with data, the matched point in it nearest its centre (-1: none).
std::vector<int> NearestPointPerCell(const KrigingPoints& kriging_points, const Raster& dem) {
  std::vector<int> nearest(dem.values.size(), -1);
  std::vector<double> distance(dem.values.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < kriging_points.positions.size(); ++i) {
    const Eigen::Vector3d& p = kriging_points.positions[i];
    int row = 0, col = 0;
    if (!dem.CellOf(p.x(), p.y(), &row, &col)) continue;
    const size_t cell = static_cast<size_t>(row) * dem.cols + col;
    const double d = std::hypot(p.x() - dem.CellCentreX(col), p.y() - dem.CellCentreY(row));
    if (!Raster::IsNoData(dem.values[cell]) && d < distance[cell])
      distance[cell] = d, nearest[cell] = static_cast<int>(i);
  }
  return nearest;
}

// One test per cell with data: the point NearestPointPerCell chose there, held out.
std::vector<HeldOutTest> HoldOutOnePointPerCell(const KrigingPoints& kriging_points,
                                                const VariogramModel& model,
                                                const KrigingOptions& o,
                                                const std::vector<int>& nearest) {
  const std::vector<Eigen::Vector3d> points = kriging_points.All();
  const std::vector<double> nugget = NuggetsOf(kriging_points, model);
  const std::vector<PointMatch> matches = MatchesOfAll(kriging_points);
  std::vector<int> held;
  for (const int i : nearest)
    if (i >= 0) held.push_back(i);
  std::vector<std::optional<HeldOutTest>> tests(held.size());
  const GridIndex grid(points, std::max(0.5, o.max_distance_m / 2));
  const std::vector<double> own_noise = OwnNoiseVariances(kriging_points, nugget);
  cv::parallel_for_(cv::Range(0, static_cast<int>(held.size())), [&](const cv::Range& range) {
    NeighbourSearch search;
    for (int k = range.start; k < range.end; ++k) {
      const int i = held[k];
      const HeldOut out{matches.empty() ? nullptr : &matches[i], nugget[i], i};
      const Eigen::Vector3d& p = points[i];
      const std::optional<Estimate> e =
          KrigeAt(grid, points, nugget, own_noise, matches, model, o, p.x(), p.y(), &search, out);
      if (!e) continue;
      // The held-out point's own noise, less what it shares with the neighbours predicting it.
      const double own = own_noise[i];
      const double noise = e->noise_variance + own - 2.0 * e->held_out_covariance;
      tests[k] =
          HeldOutTest{p.x(), p.y(), (e->z - p.z()) * (e->z - p.z()),
                      e->variance - e->noise_variance + (nugget[i] - own), std::max(noise, 0.0)};
    }
  });
  std::vector<HeldOutTest> done;
  for (const std::optional<HeldOutTest>& t : tests)
    if (t) done.push_back(*t);
  return done;
}

// The factor on the surface's variance that makes the tests' errors Gaussian with the variance
// claimed: the median of e^2 / (f s + n) is a chi-square's with one degree of freedom. The
// median, not the mean: one held-out blunder (a bush left as ground) would set a mean, and a
// cell is the mean of many points.
double SignalScale(const std::vector<HeldOutTest>& tests, const std::vector<int>& in_window) {
  constexpr double kChiSquare1Median = 0.454936;
  std::vector<double> ratio(in_window.size());
  auto median_ratio = [&](double f) {
    for (size_t k = 0; k < in_window.size(); ++k) {
      const HeldOutTest& t = tests[in_window[k]];
      ratio[k] = t.error2 / std::max(f * t.signal_variance + t.noise_variance, 1e-12);
    }
    std::nth_element(ratio.begin(), ratio.begin() + ratio.size() / 2, ratio.end());
    return ratio[ratio.size() / 2];
  };
  // The median falls as f grows: bisect on log f over twelve orders of magnitude.
  double lo = -6.0, hi = 6.0;
  if (median_ratio(std::pow(10.0, lo)) <= kChiSquare1Median) return 0.0;
  if (median_ratio(std::pow(10.0, hi)) >= kChiSquare1Median) return std::pow(10.0, hi);
  for (int k = 0; k < 40; ++k) {
    const double mid = 0.5 * (lo + hi);
    (median_ratio(std::pow(10.0, mid)) > kChiSquare1Median ? lo : hi) = mid;
  }
  return std::pow(10.0, 0.5 * (lo + hi));
}

}  // namespace

void KrigeOnto(const KrigingPoints& kriging_points, const VariogramModel& model,
               const KrigingOptions& o, Raster* dem, Raster* std_dev) {
  KrigeCells(kriging_points, model, o, dem, std_dev, nullptr);
}

double RescaleStdByHeldOutPoints(const KrigingPoints& points, const VariogramModel& model,
                                 const KrigingOptions& o, const Raster& dem,
                                 const std::vector<double>& noise_variance, Raster* std_dev) {
  if (!(o.held_out_window_m > 0.0)) return 1.0;
  // The cells the tests speak for: those holding a matched point, as each test's cell does.
  const std::vector<int> nearest = NearestPointPerCell(points, dem);
  const std::vector<HeldOutTest> tests = HoldOutOnePointPerCell(points, model, o, nearest);
  if (tests.empty()) return 1.0;
  std::vector<Eigen::Vector3d> at;
  for (const HeldOutTest& t : tests) at.emplace_back(t.x, t.y, 0.0);
  const GridIndex grid(at, o.held_out_window_m);
  std::vector<float> scale(dem.values.size(), std::numeric_limits<float>::quiet_NaN());
  cv::parallel_for_(cv::Range(0, dem.rows), [&](const cv::Range& rows) {
    std::vector<int> in_window;
    for (int row = rows.start; row < rows.end; ++row)
      for (int col = 0; col < dem.cols; ++col) {
        const size_t cell = static_cast<size_t>(row) * dem.cols + col;
        if (nearest[cell] < 0 || Raster::IsNoData(std_dev->values[cell])) continue;
        const double x = dem.CellCentreX(col), y = dem.CellCentreY(row);
        in_window.clear();
        for (int r = grid.RowOf(y) - 1; r <= grid.RowOf(y) + 1; ++r)
          for (int c = grid.ColOf(x) - 1; c <= grid.ColOf(x) + 1; ++c) {
            if (!grid.Inside(c, r)) continue;
            for (const int* k = grid.begin(c, r); k != grid.end(c, r); ++k)
              if (std::hypot(tests[*k].x - x, tests[*k].y - y) <= o.held_out_window_m)
                in_window.push_back(*k);
          }
        if (static_cast<int>(in_window.size()) < o.neighbours) continue;
        const double f = SignalScale(tests, in_window);
        const double variance = static_cast<double>(std_dev->values[cell]) * std_dev->values[cell];
        const double noise = std::min(noise_variance[cell], variance);
        std_dev->values[cell] = static_cast<float>(std::sqrt(f * (variance - noise) + noise));
        scale[cell] = static_cast<float>(f);
      }
  });
  std::vector<float> scaled;
  for (const float f : scale)
    if (std::isfinite(f)) scaled.push_back(f);
  if (scaled.empty()) return 1.0;
  std::nth_element(scaled.begin(), scaled.begin() + scaled.size() / 2, scaled.end());
  return scaled[scaled.size() / 2];
}

std::vector<CrossValidationScore> BlockCrossValidationScores(
    const KrigingPoints& points, const std::vector<VariogramModel>& models,
    const KrigingOptions& o) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const std::vector<CrossValidationScore> none(models.size(), {kNaN, kNaN, {}});
  // The held-out blocks: a seeded random choice of the squares with points.
  const GridIndex blocks(points.positions, o.cross_validation_block_m);
  std::vector<std::pair<int, int>> occupied;
  for (int r = 0; r < blocks.rows(); ++r)
    for (int c = 0; c < blocks.cols(); ++c)
      if (blocks.Count(c, r) > 0) occupied.emplace_back(c, r);
  if (occupied.size() < 4) return none;
  std::mt19937 rng(o.variogram.seed);
  std::shuffle(occupied.begin(), occupied.end(), rng);
  occupied.resize(std::min<size_t>(occupied.size(), o.cross_validation_blocks));
  // A few points of each block are predicted (spread through it): enough to rank the kinds.
  constexpr int kPredictedPerBlock = 8;
  std::vector<char> held_out(points.positions.size(), 0);
  std::vector<int> predicted_points;
  for (const auto& [c, r] : occupied) {
    const int count = blocks.Count(c, r);
    for (const int* i = blocks.begin(c, r); i != blocks.end(c, r); ++i) held_out[*i] = 1;
    for (int k = 0; k < std::min(count, kPredictedPerBlock); ++k)
      predicted_points.push_back(
          blocks.begin(c, r)[k * count / std::min(count, kPredictedPerBlock)]);
  }
  KrigingPoints training;
  training.surveyed = points.surveyed;
  for (size_t i = 0; i < points.positions.size(); ++i) {
    if (held_out[i]) continue;
    training.positions.push_back(points.positions[i]);
    if (!points.height_variances_m2.empty())
      training.height_variances_m2.push_back(points.height_variances_m2[i]);
    if (!points.matches.empty()) training.matches.push_back(points.matches[i]);
  }
  const std::vector<Eigen::Vector3d> all = training.All();
  const std::vector<PointMatch> matches = MatchesOfAll(training);
  if (all.empty()) return none;
  // Each model's nuggets of the training points, which weigh them, and of all the points, the
  // noise of a held-out one that its prediction does not know.
  std::vector<std::vector<double>> nuggets, held_out_nuggets;
  for (const VariogramModel& m : models) {
    nuggets.push_back(NuggetsOf(training, m));
    held_out_nuggets.push_back(NuggetsOf(points, m));
  }
  const GridIndex grid(all, std::max(0.5, o.max_distance_m / 2));
  // Squared errors and predicted variances per point and model; a point some model does not
  // predict is left out of all.
  const size_t kinds = models.size();
  std::vector<double> error2(predicted_points.size() * kinds, kNaN);
  std::vector<double> variance(predicted_points.size() * kinds, kNaN);
  cv::parallel_for_(
      cv::Range(0, static_cast<int>(predicted_points.size())), [&](const cv::Range& range) {
        NeighbourSearch search;
        for (int k = range.start; k < range.end; ++k) {
          const Eigen::Vector3d& p = points.positions[predicted_points[k]];
          for (size_t m = 0; m < kinds; ++m) {
            const double nugget = held_out_nuggets[m][predicted_points[k]];
            const HeldOut held_out{
                points.matches.empty() ? nullptr : &points.matches[predicted_points[k]], nugget};
            const std::optional<Estimate> e =
                KrigeAt(grid, all, nuggets[m], nuggets[m], matches, models[m], o, p.x(), p.y(),
                        &search, held_out);
            if (!e) continue;
            error2[k * kinds + m] = (e->z - p.z()) * (e->z - p.z());
            // The held-out point's noise, less what it shares with the neighbours predicting it.
            variance[k * kinds + m] = e->variance + nugget - 2.0 * e->held_out_covariance;
          }
        }
      });
  std::vector<CrossValidationScore> scores(kinds);
  std::vector<double> sum2(kinds, 0.0), sum_score(kinds, 0.0);
  int predicted = 0;
  for (size_t k = 0; k < predicted_points.size(); ++k) {
    const double* e2 = &error2[k * kinds];
    if (!std::all_of(e2, e2 + kinds, [](double v) { return std::isfinite(v); })) continue;
    for (size_t m = 0; m < kinds; ++m) {
      // Floored: a point without noise predicted exactly has no score.
      const double v = std::max(variance[k * kinds + m], 1e-12);
      sum2[m] += e2[m];
      scores[m].point_scores.push_back(e2[m] / v + std::log(v));
      sum_score[m] += scores[m].point_scores.back();
    }
    ++predicted;
  }
  if (predicted == 0) return none;
  for (size_t m = 0; m < kinds; ++m) {
    scores[m].rms_m = std::sqrt(sum2[m] / predicted);
    scores[m].log_score = sum_score[m] / predicted;
  }
  return scores;
}

size_t ChooseKind(const std::vector<CrossValidationScore>& scores, size_t fallback) {
  size_t best = fallback;
  for (size_t k = 0; k < scores.size(); ++k)
    if (std::isfinite(scores[k].log_score) && !(scores[k].log_score >= scores[best].log_score))
      best = k;
  const std::vector<double>& a = scores[best].point_scores;
  const std::vector<double>& b = scores[fallback].point_scores;
  if (best == fallback || a.size() != b.size() || a.size() < 2) return best;
  double sum = 0.0, sum2 = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += a[i] - b[i], sum2 += (a[i] - b[i]) * (a[i] - b[i]);
  const double n = static_cast<double>(a.size()), mean = sum / n;
  const double standard_error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
  return mean < -2.0 * standard_error ? best : fallback;
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
      o.linear_drift ? ResidualsFromPlane(thinned.positions) : thinned.positions, o.variogram,
      o.signal_variogram ? thinned.height_variances_m2 : std::vector<double>{}, thinned.matches);
  // The kind of variogram that predicts held-out ground best, its heights and their std: the
  // fits differ most in how they bridge gaps, which their fit to the variogram's bins does not
  // show.
  const std::vector<VariogramModel> fits = FitVariogramOfEachKind(result.experimental);
  result.model = BestFit(fits);
  if (o.cross_validation_blocks > 0) {
    const std::vector<CrossValidationScore> scores = BlockCrossValidationScores(thinned, fits, o);
    size_t fallback = 0;
    for (size_t k = 0; k < fits.size(); ++k) {
      if (!std::isfinite(scores[k].log_score)) continue;  // too few points to hold any out
      result.cross_validation.push_back({fits[k], scores[k].rms_m, scores[k].log_score});
      if (fits[k].kind == result.model.kind) fallback = k;
    }
    if (!result.cross_validation.empty()) result.model = fits[ChooseKind(scores, fallback)];
  }
  result.dem = grid;
  std::vector<double> noise_variance;
  KrigeCells(thinned, result.model, o, &result.dem, &result.std, &noise_variance);
  result.median_signal_scale =
      RescaleStdByHeldOutPoints(thinned, result.model, o, result.dem, noise_variance, &result.std);
  return result;
}

}  // namespace ts
