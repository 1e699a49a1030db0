#include "processing/dem/free_space.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace ts {

bool FreeSpaceOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// The DEM's bilinear surface over one fine square: at (u, v) in [0, 1]^2 from its top left
// corner (u east, v south, in squares), a + b u + c v + d u v, and the highest it reaches (at a
// corner). A square that straddles two cells' patches (a ceiling square that does not divide
// the cell) has no one such form: b is NaN, and the highest is that of every centre it
// depends on. No surface (a cell without data): the highest is NaN.
struct SquareSurface {
  float a = 0.0f, b = 0.0f, c = 0.0f, d = 0.0f;
  float highest = std::numeric_limits<float>::quiet_NaN();
};

std::vector<SquareSurface> SurfacePerSquare(const Raster& grid, int ratio) {
  const int cols = grid.cols * ratio, rows = grid.rows * ratio;
  const double fine_m = grid.cell_m / ratio;
  std::vector<SquareSurface> surfaces(static_cast<size_t>(cols) * rows);
  auto patch = [&](double offset_m) {  // the index of the patch's first centre, along an axis
    return static_cast<int>(std::floor(offset_m / grid.cell_m - 0.5));
  };
  constexpr double kInset = 1e-9;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double x0 = c * fine_m + kInset, x1 = (c + 1) * fine_m - kInset;
      const double y0 = r * fine_m + kInset, y1 = (r + 1) * fine_m - kInset;  // down from the top
      SquareSurface& s = surfaces[static_cast<size_t>(r) * cols + c];
      if (patch(x0) == patch(x1) && patch(y0) == patch(y1)) {
        auto at = [&](double x, double y) {
          return grid.Interpolate(grid.min_x_m + x, grid.max_y_m - y);
        };
        const double z00 = at(x0, y0), z10 = at(x1, y0), z01 = at(x0, y1), z11 = at(x1, y1);
        s.a = static_cast<float>(z00), s.b = static_cast<float>(z10 - z00);
        s.c = static_cast<float>(z01 - z00), s.d = static_cast<float>(z11 - z10 - z01 + z00);
        s.highest = static_cast<float>(std::max({z00, z10, z01, z11}));
        if (!std::isfinite(z00 + z10 + z01 + z11)) s.highest = std::nanf("");
        continue;
      }
      s.b = std::nanf("");
      double top = -kNone;
      for (int rr = std::max(0, patch(y0)); rr <= std::min(grid.rows - 1, patch(y1) + 1); ++rr)
        for (int cc = std::max(0, patch(x0)); cc <= std::min(grid.cols - 1, patch(x1) + 1); ++cc)
          top = Raster::IsNoData(grid.at(rr, cc)) ? kNone : std::max(top, double{grid.at(rr, cc)});
      if (top != kNone) s.highest = static_cast<float>(top);
    }
  return surfaces;
}

// Per fine square of the DEM's extent, the lowest line and the line that passes least above
// the DEM (the surface the lines are drawn over), each with where it passed. The lowest is the
// square's ceiling; the closest binds the surface: within a square the bilinear surface can
// rise more than the lines do (a steep cell beside a low one), and a line that is not the
// lowest then passes under it where it is high.
struct FineCeilings {
  struct Square {
    SightLineCeilings::Ceiling lowest{0.0, 0.0, kNone, 0.0};  // height kNone: no line
    // The closest line: where it passed (in squares from the square's corner) and its height
    // there, and its height above the DEM (infinite: none over the DEM's data).
    float closest_du = 0.0f, closest_dv = 0.0f, closest_height = 0.0f;
    float clearance = std::numeric_limits<float>::infinity();
  };
  FineCeilings(const Raster& grid, int ratio)
      : ratio(ratio),
        cols(grid.cols * ratio),
        rows(grid.rows * ratio),
        cell_m(grid.cell_m / ratio),
        min_x(grid.min_x_m),
        max_y(grid.max_y_m),
        squares(static_cast<size_t>(cols) * rows) {}
  // A point of a line over square (r, c) of `grid`, whose surfaces are SurfacePerSquare's;
  // true where it passes under the surface. A point on the square's edge is taken a hair inside
  // it: on the grid's outermost half cell the surface is the nearest cell's, which steps at the
  // squares' edges, and the square's is the one the line passed over.
  bool Add(int r, int c, const Eigen::Vector3d& q, double landing, const Raster& grid,
           const std::vector<SquareSurface>& surfaces) {
    if (c < 0 || r < 0 || c >= cols || r >= rows) return false;
    constexpr double kHair = 1e-6;  // of a square
    const double du = std::clamp((q.x() - min_x) / cell_m - c, kHair, 1.0 - kHair);
    const double dv = std::clamp((max_y - q.y()) / cell_m - r, kHair, 1.0 - kHair);
    const double h = q.z();
    const size_t i = static_cast<size_t>(r) * cols + c;
    Square& e = squares[i];
    if (h < e.lowest.height)
      e.lowest = {min_x + (c + du) * cell_m, max_y - (r + dv) * cell_m, h, landing};
    // The surface under the line is worked out only where the line may pass under it or
    // closer to it than the closest so far (it is no higher than its highest in the square).
    const SquareSurface& s = surfaces[i];
    if (!(h - s.highest < std::max(e.clearance, 0.0f))) return false;
    const double ground =
        std::isnan(s.b) ? grid.Interpolate(min_x + (c + du) * cell_m, max_y - (r + dv) * cell_m)
                        : s.a + s.b * du + s.c * dv + s.d * du * dv;
    const float above = static_cast<float>(h - ground);
    if (above < e.clearance) {
      e.clearance = above, e.closest_height = static_cast<float>(h);
      e.closest_du = static_cast<float>(du), e.closest_dv = static_cast<float>(dv);
    }
    return above < 0.0f;
  }
  void Merge(const FineCeilings& other) {
    for (size_t i = 0; i < squares.size(); ++i) {
      Square& e = squares[i];
      const Square& o = other.squares[i];
      if (o.lowest.height < e.lowest.height) e.lowest = o.lowest;
      if (o.clearance < e.clearance) {
        e.clearance = o.clearance, e.closest_height = o.closest_height;
        e.closest_du = o.closest_du, e.closest_dv = o.closest_dv;
      }
    }
  }
  // Square (r, c)'s closest line as a ceiling, if any passed over the DEM's data.
  bool Closest(int r, int c, SightLineCeilings::Ceiling* out) const {
    const Square& e = squares[static_cast<size_t>(r) * cols + c];
    if (!std::isfinite(e.clearance)) return false;
    *out = {min_x + (c + e.closest_du) * cell_m, max_y - (r + e.closest_dv) * cell_m,
            e.closest_height, 0.0};
    return true;
  }
  int ratio, cols, rows;
  double cell_m, min_x, max_y;
  std::vector<Square> squares;
};

// Where a line counts over the grid: the stretch of its run (from the camera, horizontally)
// over the grid, up to end_gap_min_m and its range's end_sigmas short of its point. False
// where there is none.
bool CountingStretch(const SightLine& line, const Raster& grid, double end_gap_min_m,
                     double end_sigmas, double* from, double* to) {
  const Eigen::Vector3d d = line.point - line.camera;
  const double run = d.head<2>().norm(), length = d.norm();
  if (!(run > 0.0) || !std::isfinite(length)) return false;
  // The range's sigma, as a horizontal distance.
  const double end_gap = std::max(end_gap_min_m, end_sigmas * line.range_sigma_m * run / length);
  // Only the stretch over the grid (slabs in x and y).
  *from = 0.0, *to = run - end_gap;
  const double max_x = grid.min_x_m + grid.cols * grid.cell_m;
  const double min_y = grid.max_y_m - grid.rows * grid.cell_m;
  const double bounds[2][2] = {{grid.min_x_m, max_x}, {min_y, grid.max_y_m}};
  for (int axis = 0; axis < 2; ++axis) {
    const double start = line.camera[axis], per_m = d[axis] / run;
    if (per_m == 0.0) {
      if (start < bounds[axis][0] || start > bounds[axis][1]) return false;
      continue;
    }
    double a = (bounds[axis][0] - start) / per_m, b = (bounds[axis][1] - start) / per_m;
    if (a > b) std::swap(a, b);
    *from = std::max(*from, a), *to = std::min(*to, b);
  }
  return *to > *from;
}

// Every step_m of a line's counting stretch.
template <class Visit>
void VisitLine(const SightLine& line, const Raster& grid, double step_m, double end_gap_min_m,
               double end_sigmas, const Visit& visit) {
  double from = 0.0, to = 0.0;
  if (!CountingStretch(line, grid, end_gap_min_m, end_sigmas, &from, &to)) return;
  const Eigen::Vector3d d = line.point - line.camera;
  const double run = d.head<2>().norm();
  const double first =
      0.5 * step_m + std::ceil(std::max(0.0, from - 0.5 * step_m) / step_m) * step_m;
  for (double s = first; s < to; s += step_m)
    if (!visit(Eigen::Vector3d(line.camera + d * (s / run)))) return;
}

// Along one axis, the run distances at which a line crosses the fine squares' edges, in order:
// the edges lie at origin + k cell_m (k whole), the line moves per_m along the axis per metre
// of run from `start` at run 0.
class EdgeCrossings {
 public:
  EdgeCrossings(double start, double per_m, double origin, double cell_m, double from) {
    if (per_m == 0.0) return;
    step_ = cell_m / std::abs(per_m);
    const double k = (start + per_m * from - origin) / cell_m;
    const double edge = per_m > 0.0 ? std::floor(k) + 1.0 : std::ceil(k) - 1.0;
    next_ = (origin + edge * cell_m - start) / per_m;
    if (next_ <= from + kOnEdge) next_ += step_;  // `from` on an edge, but for rounding
  }
  static constexpr double kOnEdge = 1e-9;  // m of run
  double next() const { return next_; }
  void Advance() { next_ += step_; }

 private:
  double next_ = kNone, step_ = 0.0;
};

// Each stretch of a line over one fine square, its ends offered to that square: along a line
// over a square the bilinear surface is all but straight, so the line is lowest over it, and
// nearest the surface, at the square's edges (or where it stops counting). The squares are
// stepped through edge by edge. True where the line passes under the surface somewhere.
bool AddLine(const SightLine& line, const Raster& grid, const std::vector<SquareSurface>& surfaces,
             double end_sigmas, FineCeilings* fine) {
  double from = 0.0, to = 0.0;
  if (!CountingStretch(line, grid, grid.cell_m, end_sigmas, &from, &to)) return false;
  const Eigen::Vector3d d = line.point - line.camera;
  const double run = d.head<2>().norm();
  auto at = [&](double s) { return Eigen::Vector3d(line.camera + d * (s / run)); };
  // y's edges counted from the top (rows grow southward): the line moves -d.y per metre there.
  EdgeCrossings x(line.camera.x(), d.x() / run, fine->min_x, fine->cell_m, from);
  EdgeCrossings y(-line.camera.y(), -d.y() / run, -fine->max_y, fine->cell_m, from);
  const int step_c = d.x() > 0.0 ? 1 : -1, step_r = d.y() > 0.0 ? -1 : 1;
  Eigen::Vector3d q = at(from);
  // The first square: where the line runs before its first edge.
  const Eigen::Vector3d middle = at(0.5 * (from + std::min({x.next(), y.next(), to})));
  int c = static_cast<int>(std::floor((middle.x() - fine->min_x) / fine->cell_m));
  int r = static_cast<int>(std::floor((fine->max_y - middle.y()) / fine->cell_m));
  const double landing = line.point.z();
  auto add = [&](const Eigen::Vector3d& p) { return fine->Add(r, c, p, landing, grid, surfaces); };
  bool under = add(q);
  for (;;) {
    const bool along_x = x.next() < y.next();
    const double edge = along_x ? x.next() : y.next();
    if (!(edge < to)) break;
    q = at(edge);
    under |= add(q);
    if (along_x) {
      x.Advance(), c += step_c;
    } else {
      y.Advance(), r += step_r;
    }
    under |= add(q);
  }
  under |= add(at(to));
  return under;
}

// The lines `which` (indices into `lines`) over the fine squares of `grid`, in chunks of at
// least kLinesPerChunk lines (at most 16), merged in order: the same result on any number of
// threads. under: per line, 1 where it passed under the grid's surface (lines not in `which`
// untouched).
FineCeilings WalkLines(const std::vector<SightLine>& lines, const std::vector<size_t>& which,
                       const Raster& grid, int ratio, double end_sigmas,
                       std::vector<uint8_t>* under) {
  constexpr size_t kLinesPerChunk = 2048;
  const int chunk_count =
      static_cast<int>(std::clamp<size_t>(which.size() / kLinesPerChunk, 1, 16));
  const std::vector<SquareSurface> surfaces = SurfacePerSquare(grid, ratio);
  std::vector<FineCeilings> chunks(chunk_count, FineCeilings(grid, ratio));
  cv::parallel_for_(cv::Range(0, chunk_count), [&](const cv::Range& range) {
    for (int k = range.start; k < range.end; ++k)
      for (size_t i = k; i < which.size(); i += chunk_count)
        (*under)[which[i]] = AddLine(lines[which[i]], grid, surfaces, end_sigmas, &chunks[k]);
  });
  for (int k = 1; k < chunk_count; ++k) chunks[0].Merge(chunks[k]);
  return std::move(chunks[0]);
}

int FineRatio(const Raster& grid, const FreeSpaceOptions& o) {
  return std::max(1, static_cast<int>(std::lround(grid.cell_m / o.ceiling_cell_m)));
}

// A line's height over its camera per metre of run.
double Rise(const SightLine& l) {
  const double run = (l.point - l.camera).head<2>().norm();
  return run > 0.0 ? (l.point.z() - l.camera.z()) / run : kNone;
}

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

// The lines with a finite camera and point, every one: lines of one camera to the points of
// one small square are not all under the one that rises least where the ground slopes across
// them (terraces seed 2: a riser's face beside a lower tread, 0.13-0.19 m).
std::vector<size_t> FiniteLines(const std::vector<SightLine>& lines) {
  std::vector<size_t> finite;
  finite.reserve(lines.size());
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].point.allFinite() && lines[i].camera.allFinite()) finite.push_back(i);
  return finite;
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

// Each ceiling as a half-space over the four cells of the DEM's bilinear interpolation there:
// w'z <= height. Ceilings over a cell without data are left out.
struct BilinearConstraint {
  size_t cell[4];
  double weight[4];
  double height, weight_norm2;
};

std::vector<BilinearConstraint> BilinearConstraints(
    const std::vector<SightLineCeilings::Ceiling>& ceilings, const Raster& dem) {
  std::vector<BilinearConstraint> constraints;
  for (const SightLineCeilings::Ceiling& e : ceilings) {
    const double fc = (e.x - dem.min_x_m) / dem.cell_m - 0.5;
    const double fr = (dem.max_y_m - e.y) / dem.cell_m - 0.5;
    int c0 = static_cast<int>(std::floor(fc)), r0 = static_cast<int>(std::floor(fr));
    double tx = fc - c0, ty = fr - r0;
    // On the outermost half cell the surface is the nearest cell's, in both directions, as
    // Raster::Interpolate has it (not a blend along the edge: the nearest cell may stand above).
    if (c0 < 0 || r0 < 0 || c0 + 1 >= dem.cols || r0 + 1 >= dem.rows) {
      const int c = static_cast<int>(std::lround(fc)), r = static_cast<int>(std::lround(fr));
      c0 = std::clamp(c, 0, dem.cols - 2), tx = c - c0;
      r0 = std::clamp(r, 0, dem.rows - 2), ty = r - r0;
    }
    if (c0 < 0 || r0 < 0) continue;  // a grid one cell wide
    BilinearConstraint k{
        {}, {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty}, e.height, 0.0};
    bool data = true;
    for (int j = 0; j < 4; ++j) {
      const int r = r0 + j / 2, c = c0 + j % 2;
      k.cell[j] = static_cast<size_t>(r) * dem.cols + c;
      data = data && (k.weight[j] == 0.0 || !Raster::IsNoData(dem.values[k.cell[j]]));
      k.weight_norm2 += k.weight[j] * k.weight[j];
    }
    if (data) constraints.push_back(k);
  }
  return constraints;
}

// Each constraint in turn met by the least change of z (a projection onto its half-space),
// where the surface stands more than tolerance_m above it. That only lowers cells, with
// weights that are never negative, so it cannot undo a constraint met before.
void ProjectBelow(const std::vector<BilinearConstraint>& constraints, double tolerance_m,
                  std::vector<double>* z) {
  for (const BilinearConstraint& k : constraints) {
    double surface = 0.0;
    for (int j = 0; j < 4; ++j) surface += k.weight[j] * (*z)[k.cell[j]];
    const double excess = surface - k.height;
    if (excess <= tolerance_m) continue;
    for (int j = 0; j < 4; ++j) (*z)[k.cell[j]] -= k.weight[j] * excess / k.weight_norm2;
  }
}

// A line this little under the surface (m) is taken for one that meets it: the DEM is stored
// in single precision.
constexpr double kMet = 1e-4;

}  // namespace

SightLineCeilings FindSightLineCeilings(const std::vector<SightLine>& lines, const Raster& grid,
                                        const FreeSpaceOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("FreeSpaceOptions: " + why);
  const int ratio = FineRatio(grid, o);
  SightLineCeilings out;
  const std::vector<size_t> walked = FiniteLines(lines);
  std::vector<uint8_t> under(lines.size(), 0);
  const FineCeilings fine = WalkLines(lines, walked, grid, ratio, o.end_sigmas, &under);
  for (const size_t i : walked)
    if (under[i]) out.under_grid.push_back(lines[i]);
  out.per_cell = Raster::Make(grid.min_x_m, grid.max_y_m, grid.cell_m, grid.cols, grid.rows);
  out.per_cell.crs_wkt = grid.crs_wkt;
  out.landing_per_cell = out.per_cell;
  for (int r = 0; r < fine.rows; ++r)
    for (int c = 0; c < fine.cols; ++c) {
      const SightLineCeilings::Ceiling& e =
          fine.squares[static_cast<size_t>(r) * fine.cols + c].lowest;
      if (e.height == kNone) continue;
      out.ceilings.push_back(e);
      SightLineCeilings::Ceiling closest;
      if (fine.Closest(r, c, &closest) && closest.height != static_cast<float>(e.height))
        out.ceilings.push_back(closest);
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
  const std::vector<float> before = dem->values;
  std::vector<double> z(dem->values.begin(), dem->values.end());
  ProjectBelow(BilinearConstraints(ceilings.ceilings, *dem), o.tolerance_m, &z);
  // The lines that passed under the DEM, again over the lowered one: a square's closest line to
  // the first need not bind the second (the projections moved its cells unevenly). Each round
  // meets the closest line under each square; the lines still under it go round again.
  std::vector<SightLine> under = ceilings.under_grid;
  constexpr int kMaxRounds = 8;
  for (int round = 0; round < kMaxRounds && !under.empty(); ++round) {
    for (size_t i = 0; i < z.size(); ++i)
      if (!Raster::IsNoData(before[i])) dem->values[i] = static_cast<float>(z[i]);
    std::vector<size_t> all(under.size());
    std::iota(all.begin(), all.end(), size_t{0});
    std::vector<uint8_t> still(under.size(), 0);
    const FineCeilings fine = WalkLines(under, all, *dem, FineRatio(*dem, o), o.end_sigmas, &still);
    std::vector<SightLineCeilings::Ceiling> binding;
    for (int r = 0; r < fine.rows; ++r)
      for (int c = 0; c < fine.cols; ++c) {
        SightLineCeilings::Ceiling closest;
        if (fine.Closest(r, c, &closest) &&
            closest.height < dem->Interpolate(closest.x, closest.y) - o.tolerance_m - kMet)
          binding.push_back(closest);
      }
    if (binding.empty()) break;
    ProjectBelow(BilinearConstraints(binding, *dem), o.tolerance_m, &z);
    size_t kept = 0;
    for (size_t i = 0; i < under.size(); ++i)
      if (still[i]) under[kept++] = under[i];
    under.resize(kept);
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
