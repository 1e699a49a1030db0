#include "processing/dem/free_space.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace ts {

bool FreeSpaceOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// The lowest line per fine square of the DEM's extent, with where it passed.
struct FineCeilings {
  FineCeilings(const Raster& grid, int ratio)
      : ratio(ratio),
        cols(grid.cols * ratio),
        rows(grid.rows * ratio),
        cell_m(grid.cell_m / ratio),
        min_x(grid.min_x_m),
        max_y(grid.max_y_m),
        lowest(static_cast<size_t>(cols) * rows, {0.0, 0.0, kNone, 0.0}) {}
  void Add(double x, double y, double h, double landing) {
    const int c = static_cast<int>(std::floor((x - min_x) / cell_m));
    const int r = static_cast<int>(std::floor((max_y - y) / cell_m));
    if (c < 0 || r < 0 || c >= cols || r >= rows) return;
    SightLineCeilings::Ceiling& e = lowest[static_cast<size_t>(r) * cols + c];
    if (h < e.height) e = {x, y, h, landing};
  }
  void Merge(const FineCeilings& other) {
    for (size_t i = 0; i < lowest.size(); ++i)
      if (other.lowest[i].height < lowest[i].height) lowest[i] = other.lowest[i];
  }
  int ratio, cols, rows;
  double cell_m, min_x, max_y;
  std::vector<SightLineCeilings::Ceiling> lowest;  // height kNone: no line
};

// Where a line counts over the grid: every step_m of its run (from the camera, horizontally),
// up to end_gap_min_m and its range's end_sigmas short of its point.
template <class Visit>
void VisitLine(const SightLine& line, const Raster& grid, double step_m, double end_gap_min_m,
               double end_sigmas, const Visit& visit) {
  const Eigen::Vector3d d = line.point - line.camera;
  const double run = d.head<2>().norm(), length = d.norm();
  if (!(run > 0.0) || !std::isfinite(length)) return;
  // The range's sigma, as a horizontal distance.
  const double end_gap = std::max(end_gap_min_m, end_sigmas * line.range_sigma_m * run / length);
  // Only the stretch over the grid (slabs in x and y).
  double from = 0.0, to = run - end_gap;
  const double max_x = grid.min_x_m + grid.cols * grid.cell_m;
  const double min_y = grid.max_y_m - grid.rows * grid.cell_m;
  const double bounds[2][2] = {{grid.min_x_m, max_x}, {min_y, grid.max_y_m}};
  for (int axis = 0; axis < 2; ++axis) {
    const double start = line.camera[axis], per_m = d[axis] / run;
    if (per_m == 0.0) {
      if (start < bounds[axis][0] || start > bounds[axis][1]) return;
      continue;
    }
    double a = (bounds[axis][0] - start) / per_m, b = (bounds[axis][1] - start) / per_m;
    if (a > b) std::swap(a, b);
    from = std::max(from, a), to = std::min(to, b);
  }
  const double first =
      0.5 * step_m + std::ceil(std::max(0.0, from - 0.5 * step_m) / step_m) * step_m;
  for (double s = first; s < to; s += step_m)
    if (!visit(Eigen::Vector3d(line.camera + d * (s / run)))) return;
}

void AddLine(const SightLine& line, const Raster& grid, double end_sigmas, FineCeilings* fine) {
  VisitLine(line, grid, 0.5 * fine->cell_m, grid.cell_m, end_sigmas, [&](const Eigen::Vector3d& q) {
    fine->Add(q.x(), q.y(), q.z(), line.point.z());
    return true;
  });
}

bool IsMismatch(const SightLine& line, const Raster& dem, const Raster& kriging_std,
                const FreeSpaceOptions& o) {
  bool under = false;
  VisitLine(line, dem, 0.5 * dem.cell_m, dem.cell_m, o.end_sigmas, [&](const Eigen::Vector3d& q) {
    const double ground = dem.Interpolate(q.x(), q.y());
    const double sigma = kriging_std.Interpolate(q.x(), q.y());
    under = std::isfinite(ground) && std::isfinite(sigma) &&
            ground - q.z() > o.mismatch_sigmas * sigma + dem.cell_m;
    return !under;
  });
  return under;
}

// A line's height over its camera per metre of run.
double Rise(const SightLine& l) {
  const double run = (l.point - l.camera).head<2>().norm();
  return run > 0.0 ? (l.point.z() - l.camera.z()) / run : kNone;
}

// The lines grouped by camera and ceiling_cell_m square of their points' positions, each
// group in the order its lines rise (their height over the camera per metre run): the lines of
// one camera to the points of one small square run side by side, and the first is below the
// others all along (to within the square's width). Not the line to the lowest point: above
// the eye a farther point a little higher can lie under a lower, nearer one's line (a riser
// seen from below). Line indices, and where each group starts (and, last, the end).
struct LinesBySquare {
  std::vector<size_t> line;
  std::vector<size_t> start;
};

// Per line, its camera's and its point's square's key (-1: not a finite line).
std::vector<int64_t> CameraSquareKeys(const std::vector<SightLine>& lines, double cell_m) {
  std::map<std::array<double, 3>, int64_t> cameras;
  std::vector<int64_t> key(lines.size(), -1);
  constexpr int64_t kSpan = int64_t{1} << 21;  // squares per axis; the camera's index above
  for (size_t i = 0; i < lines.size(); ++i) {
    const SightLine& l = lines[i];
    if (!l.point.allFinite() || !l.camera.allFinite()) continue;
    const int64_t col = static_cast<int64_t>(std::floor(l.point.x() / cell_m)) + kSpan / 2;
    const int64_t row = static_cast<int64_t>(std::floor(l.point.y() / cell_m)) + kSpan / 2;
    if (col < 0 || row < 0 || col >= kSpan || row >= kSpan) continue;
    const auto [it, added] = cameras.try_emplace({l.camera.x(), l.camera.y(), l.camera.z()},
                                                 static_cast<int64_t>(cameras.size()));
    key[i] = (it->second * kSpan + col) * kSpan + row;
  }
  return key;
}

LinesBySquare GroupBySquare(const std::vector<SightLine>& lines, double cell_m) {
  struct Keyed {
    int64_t key;
    double rise;
    size_t index;
  };
  const std::vector<int64_t> key = CameraSquareKeys(lines, cell_m);
  std::vector<Keyed> keyed;
  keyed.reserve(lines.size());
  for (size_t i = 0; i < lines.size(); ++i)
    if (key[i] >= 0) keyed.push_back({key[i], Rise(lines[i]), i});
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return std::tie(a.key, a.rise, a.index) < std::tie(b.key, b.rise, b.index);
  });
  LinesBySquare groups;
  for (size_t k = 0; k < keyed.size(); ++k) {
    if (k == 0 || keyed[k - 1].key != keyed[k].key) groups.start.push_back(k);
    groups.line.push_back(keyed[k].index);
  }
  groups.start.push_back(keyed.size());
  return groups;
}

// Per group, its lowest line (the near ground is matched densely, so this leaves a fraction of
// the lines); with a kriging std, its lowest line that is no far mismatch, those before it
// counted in `mismatched`.
std::vector<size_t> LowestLinePerSquare(const std::vector<SightLine>& lines,
                                        const FreeSpaceOptions& o, const Raster& dem,
                                        const Raster* kriging_std, int* mismatched) {
  if (kriging_std && kriging_std->values.size() != dem.values.size())
    throw std::invalid_argument("FindSightLineCeilings: the std grid differs from the DEM's");
  const LinesBySquare groups = GroupBySquare(lines, o.ceiling_cell_m);
  const int count = static_cast<int>(groups.start.size()) - 1;
  constexpr size_t kNoLine = std::numeric_limits<size_t>::max();
  std::vector<size_t> chosen(count, kNoLine);
  std::vector<int> dropped(count, 0);
  cv::parallel_for_(cv::Range(0, count), [&](const cv::Range& range) {
    for (int g = range.start; g < range.end; ++g)
      for (size_t k = groups.start[g]; k < groups.start[g + 1]; ++k) {
        const size_t i = groups.line[k];
        if (!kriging_std || !lines[i].far || !IsMismatch(lines[i], dem, *kriging_std, o)) {
          chosen[g] = i;
          break;
        }
        ++dropped[g];
      }
  });
  std::vector<size_t> lowest;
  for (int g = 0; g < count; ++g) {
    if (chosen[g] != kNoLine) lowest.push_back(chosen[g]);
    *mismatched += dropped[g];
  }
  return lowest;
}

// Per ceiling_cell_m square over the ground points' extent: the second lowest point's height
// less the square's diagonal and sigmas of its height sigma (nodata: fewer than two points).
Raster SeenGroundFloor(const std::vector<Eigen::Vector3d>& ground,
                       const std::vector<double>& variances_m2, const FreeSpaceOptions& o) {
  Eigen::AlignedBox2d box;
  for (const Eigen::Vector3d& p : ground)
    if (p.allFinite()) box.extend(p.head<2>());
  const double cell = o.ceiling_cell_m;
  if (box.isEmpty()) return Raster::Make(0.0, 0.0, cell, 0, 0);
  const int cols = static_cast<int>(std::floor(box.sizes().x() / cell)) + 1;
  const int rows = static_cast<int>(std::floor(box.sizes().y() / cell)) + 1;
  Raster floor = Raster::Make(box.min().x(), box.max().y(), cell, cols, rows);
  struct Lowest {
    double z[2] = {kNone, kNone};
    double variance[2] = {0.0, 0.0};
  };
  std::vector<Lowest> lowest(floor.values.size());
  for (size_t i = 0; i < ground.size(); ++i) {
    int r = 0, c = 0;
    if (!ground[i].allFinite() || !floor.CellOf(ground[i].x(), ground[i].y(), &r, &c)) continue;
    Lowest& l = lowest[static_cast<size_t>(r) * cols + c];
    const double z = ground[i].z(), v = variances_m2.empty() ? 0.0 : variances_m2[i];
    if (z < l.z[0]) {
      l.z[1] = l.z[0], l.variance[1] = l.variance[0];
      l.z[0] = z, l.variance[0] = v;
    } else if (z < l.z[1]) {
      l.z[1] = z, l.variance[1] = v;
    }
  }
  const double diagonal = std::sqrt(2.0) * cell;
  for (size_t k = 0; k < lowest.size(); ++k)
    if (lowest[k].z[1] != kNone)
      floor.values[k] = static_cast<float>(lowest[k].z[1] - diagonal -
                                           o.seen_ground_sigmas * std::sqrt(lowest[k].variance[1]));
  return floor;
}

bool PassesThroughSeenGround(const SightLine& line, const Raster& floor, double min_gap_m,
                             const FreeSpaceOptions& o) {
  int squares = 0;
  int last_r = -1, last_c = -1;
  VisitLine(line, floor, 0.5 * floor.cell_m, min_gap_m, o.end_sigmas,
            [&](const Eigen::Vector3d& q) {
              int r = 0, c = 0;
              if (!floor.CellOf(q.x(), q.y(), &r, &c) || (r == last_r && c == last_c)) return true;
              const float seen = floor.at(r, c);
              if (Raster::IsNoData(seen) || q.z() >= seen) return true;
              last_r = r, last_c = c;
              return ++squares < o.seen_ground_witnesses;
            });
  return squares >= o.seen_ground_witnesses;
}

}  // namespace

SightLineCeilings FindSightLineCeilings(const std::vector<SightLine>& lines, const Raster& grid,
                                        const FreeSpaceOptions& o, const Raster* kriging_std) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("FreeSpaceOptions: " + why);
  const int ratio = std::max(1, static_cast<int>(std::lround(grid.cell_m / o.ceiling_cell_m)));
  SightLineCeilings out;
  const std::vector<size_t> lowest =
      LowestLinePerSquare(lines, o, grid, kriging_std, &out.mismatched);
  // Fixed chunks, merged in order: the same result on any number of threads.
  constexpr int kChunks = 16;
  std::vector<FineCeilings> chunks(kChunks, FineCeilings(grid, ratio));
  cv::parallel_for_(cv::Range(0, kChunks), [&](const cv::Range& range) {
    for (int k = range.start; k < range.end; ++k)
      for (size_t i = k; i < lowest.size(); i += kChunks)
        AddLine(lines[lowest[i]], grid, o.end_sigmas, &chunks[k]);
  });
  for (int k = 1; k < kChunks; ++k) chunks[0].Merge(chunks[k]);
  const FineCeilings& fine = chunks[0];
  out.per_cell = Raster::Make(grid.min_x_m, grid.max_y_m, grid.cell_m, grid.cols, grid.rows);
  out.per_cell.crs_wkt = grid.crs_wkt;
  out.landing_per_cell = out.per_cell;
  for (int r = 0; r < fine.rows; ++r)
    for (int c = 0; c < fine.cols; ++c) {
      const SightLineCeilings::Ceiling& e = fine.lowest[static_cast<size_t>(r) * fine.cols + c];
      if (e.height == kNone) continue;
      out.ceilings.push_back(e);
      float& cell = out.per_cell.at(r / ratio, c / ratio);
      if (!Raster::IsNoData(cell) && cell <= e.height) continue;
      cell = static_cast<float>(e.height);
      out.landing_per_cell.at(r / ratio, c / ratio) = static_cast<float>(e.landing);
    }
  return out;
}

std::vector<uint8_t> FindLinesThroughSeenGround(const std::vector<SightLine>& lines,
                                                const std::vector<Eigen::Vector3d>& ground,
                                                const std::vector<double>& ground_variances_m2,
                                                double min_gap_m, const FreeSpaceOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("FreeSpaceOptions: " + why);
  if (!ground_variances_m2.empty() && ground_variances_m2.size() != ground.size())
    throw std::invalid_argument(
        "FindLinesThroughSeenGround: one height variance per point or none");
  std::vector<uint8_t> through(lines.size(), 0);
  if (!o.enabled) return through;
  const Raster floor = SeenGroundFloor(ground, ground_variances_m2, o);
  if (floor.values.empty()) return through;
  // Of one camera's lines to the points of one square min_gap_m wide, the one that rises least
  // runs below the others up to where they stop counting, beside them by less than that width
  // (a blunder behind seen ground lies metres under it): only where it went through are the
  // others looked at.
  const std::vector<int64_t> key = CameraSquareKeys(lines, min_gap_m);
  std::unordered_map<int64_t, size_t> least;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (key[i] < 0) continue;
    auto [it, added] = least.try_emplace(key[i], i);
    if (!added && Rise(lines[i]) < Rise(lines[it->second])) it->second = i;
  }
  std::vector<size_t> first;
  first.reserve(least.size());
  for (const auto& [k, i] : least) first.push_back(i);
  std::sort(first.begin(), first.end());
  auto judge = [&](const std::vector<size_t>& which) {
    cv::parallel_for_(cv::Range(0, static_cast<int>(which.size())), [&](const cv::Range& range) {
      for (int j = range.start; j < range.end; ++j)
        through[which[j]] = PassesThroughSeenGround(lines[which[j]], floor, min_gap_m, o);
    });
  };
  judge(first);
  std::unordered_set<int64_t> refuted;
  for (size_t i : first)
    if (through[i]) refuted.insert(key[i]);
  std::vector<size_t> rest;
  for (size_t i = 0; i < lines.size(); ++i)
    if (key[i] >= 0 && refuted.count(key[i]) && least.at(key[i]) != i) rest.push_back(i);
  judge(rest);
  return through;
}

FreeSpaceResult LowerBelowSightLines(const SightLineCeilings& ceilings, const FreeSpaceOptions& o,
                                     Raster* dem, Raster* std) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("FreeSpaceOptions: " + why);
  if (std && std->values.size() != dem->values.size())
    throw std::invalid_argument("LowerBelowSightLines: the std grid differs from the DEM's");
  FreeSpaceResult result;
  if (!o.enabled) return result;
  // Each ceiling as a half-space over the four cells of its bilinear interpolation.
  struct Constraint {
    size_t cell[4];
    double weight[4];
    double height, weight_norm2;
  };
  std::vector<Constraint> constraints;
  for (const SightLineCeilings::Ceiling& e : ceilings.ceilings) {
    const double fc = (e.x - dem->min_x_m) / dem->cell_m - 0.5;
    const double fr = (dem->max_y_m - e.y) / dem->cell_m - 0.5;
    int c0 = static_cast<int>(std::floor(fc)), r0 = static_cast<int>(std::floor(fr));
    double tx = fc - c0, ty = fr - r0;
    // On the outermost half cell the surface is the nearest cell's, in both directions, as
    // Raster::Interpolate has it (not a blend along the edge: the nearest cell may stand above).
    if (c0 < 0 || r0 < 0 || c0 + 1 >= dem->cols || r0 + 1 >= dem->rows) {
      const int c = static_cast<int>(std::lround(fc)), r = static_cast<int>(std::lround(fr));
      c0 = std::clamp(c, 0, dem->cols - 2), tx = c - c0;
      r0 = std::clamp(r, 0, dem->rows - 2), ty = r - r0;
    }
    if (c0 < 0 || r0 < 0) continue;  // a grid one cell wide
    Constraint k{{}, {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty}, e.height, 0.0};
    bool data = true;
    for (int j = 0; j < 4; ++j) {
      const int r = r0 + j / 2, c = c0 + j % 2;
      k.cell[j] = static_cast<size_t>(r) * dem->cols + c;
      data = data && (k.weight[j] == 0.0 || !Raster::IsNoData(dem->values[k.cell[j]]));
      k.weight_norm2 += k.weight[j] * k.weight[j];
    }
    if (data) constraints.push_back(k);
  }
  const std::vector<float> before = dem->values;
  std::vector<double> z(dem->values.begin(), dem->values.end());
  for (const Constraint& k : constraints) {
    double surface = 0.0;
    for (int j = 0; j < 4; ++j) surface += k.weight[j] * z[k.cell[j]];
    const double excess = surface - k.height;
    if (excess <= o.tolerance_m) continue;
    for (int j = 0; j < 4; ++j) z[k.cell[j]] -= k.weight[j] * excess / k.weight_norm2;
  }
  constexpr double kLowered = 1e-3;  // m: counted as lowered
  double lowering = 0.0;
  for (size_t i = 0; i < z.size(); ++i) {
    if (Raster::IsNoData(before[i])) continue;
    dem->values[i] = static_cast<float>(z[i]);
    const double d = before[i] - dem->values[i];
    if (d <= kLowered) continue;
    if (std && !Raster::IsNoData(std->values[i]))
      std->values[i] = static_cast<float>(std::hypot(std->values[i], d));
    ++result.cells_lowered;
    lowering += d;
    result.max_lowering_m = std::max(result.max_lowering_m, d);
  }
  if (result.cells_lowered > 0) result.mean_lowering_m = lowering / result.cells_lowered;
  return result;
}

}  // namespace ts
