#include "processing/matching/pair_matcher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <unordered_set>

#include "processing/common/median.h"

namespace ts {

PairMatchOptions PairMatchOptions::ForStation() {
  PairMatchOptions m;
  m.min_spacing_m = 0.2;
  m.lsm.half_window_px = 8;
  m.lsm.max_sigma_px = 0.075;
  m.far_lsm.max_sigma_px = 0.075;
  m.near_lsm.max_sigma_px = 0.075;
  return m;
}

bool PairMatchOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!enhance.Check(&err) || !interest.Check(&err) || !pyramid.Check(&err)) {
  } else if (!(max_depth_m > min_depth_m)) {
    err = "need min_depth_m < max_depth_m";
  } else if ((min_disparity_px >= 0) != (max_disparity_px >= 0) ||
             (max_disparity_px >= 0 && max_disparity_px <= min_disparity_px)) {
    err = "give both min_disparity_px and max_disparity_px, with max > min";
  }
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

double SecondsSince(std::chrono::steady_clock::time_point* start) {
  const auto now = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(now - *start).count();
  *start = now;
  return s;
}

// The points to match: Förstner's, or a regular grid in dense mode.
std::vector<cv::Point> Points(const cv::Mat& enhanced_left, const PairMatchOptions& o) {
  std::vector<cv::Point> points;
  if (o.dense_step_px > 0) {
    for (int v = 0; v < enhanced_left.rows; v += o.dense_step_px)
      for (int u = 0; u < enhanced_left.cols; u += o.dense_step_px) points.emplace_back(u, v);
    return points;
  }
  for (const InterestPoint& p : DetectForstner(enhanced_left, o.interest))
    points.emplace_back(static_cast<int>(std::lround(p.position_px.x())),
                        static_cast<int>(std::lround(p.position_px.y())));
  // In image order, so that consecutive windows share cache lines (Förstner's order is by
  // strength: scattered over the image).
  std::sort(points.begin(), points.end(), [](const cv::Point& a, const cv::Point& b) {
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  });
  return points;
}

// Object-space spacing of the matches on the ground: a point is tried only if no match was
// made in its cell. Across the image the cell is the spacing in pixels, s f / Z = s d / B;
// down the image the ground is foreshortened by about the camera height over the range, so
// rows are kept closer (a rig ~1.5 m above the ground is assumed: the factor only sets how
// much redundancy is dropped). Cell sides are powers of two; a point that fails leaves its
// cell free for the next one.
class SpacingFilter {
 public:
  SpacingFilter(double min_spacing_m, double baseline_m, double focal_px)
      : across_(min_spacing_m / baseline_m),
        down_(across_ * kCameraHeightM / (focal_px * baseline_m)) {}
  bool Free(int u, int v, int disparity) const {
    const int64_t key = Key(u, v, disparity);
    return key < 0 || taken_.count(key) == 0;
  }
  void Take(int u, int v, int disparity) {
    const int64_t key = Key(u, v, disparity);
    if (key >= 0) taken_.insert(key);
  }

 private:
  static constexpr double kCameraHeightM = 1.5;
  static int Level(double px) {
    return px < 2.0 ? 0 : std::min(10, static_cast<int>(std::log2(px)));
  }
  int64_t Key(int u, int v, int disparity) const {
    const int lu = Level(across_ * disparity), lv = Level(down_ * disparity * disparity);
    if (lu == 0 && lv == 0) return -1;  // every point
    return (static_cast<int64_t>(lu * 16 + lv) << 48) | (static_cast<int64_t>(v >> lv) << 24) |
           (u >> lu);
  }
  double across_, down_;
  std::unordered_set<int64_t> taken_;
};

// The map's disparity at full-resolution pixel p (in full-resolution pixels), -1 for none.
int MapDisparity(const DisparityMap& map, cv::Point p) {
  if (p.x < 0 || p.y < 0) return -1;
  const int mu = p.x >> map.level, mv = p.y >> map.level;
  if (mu >= map.disparity.cols || mv >= map.disparity.rows) return -1;
  const int coarse = map.disparity.at<int16_t>(mv, mu);
  return coarse < 0 ? -1 : coarse << map.level;
}

// Full-resolution integer disparity at (u, v) around the map's approximation.
int RefineFromMap(const DisparityMap& map, const cv::Mat& from, const cv::Mat& to, int u, int v,
                  int d_min, int d_max, int h, int sign, double* score) {
  const int approx = MapDisparity(map, {u, v});
  if (approx < 0) return -1;
  const int radius = (1 << map.level) + 1;
  return BestDisparityAt(from, to, u, v, std::max(d_min, approx - radius),
                         std::min(d_max, approx + radius), h, sign, score);
}

// One pair's images as matching uses them, its disparity range and where the windows change.
struct PairContext {
  // Wallis for finding points and searching; not for least-squares matching: its local gain
  // varies across a window differently in the two views where perspective differs (near
  // ground), a ramp LSM's linear radiometry cannot absorb (measured: -0.33 px bias below 8 m).
  cv::Mat left, right;          // Gaussian and Wallis
  cv::Mat lsm_left, lsm_right;  // Gaussian only
  ImageGradients gradients;     // of lsm_left
  // Half resolution for the near points (empty: none): pixel i of a pyrDown level is
  // centred on pixel 2i.
  cv::Mat half_left, half_right;
  ImageGradients half_gradients;
  LsmOptions half_lsm;  // near_lsm with its thresholds in half-resolution pixels
  double near_disparity = std::numeric_limits<double>::infinity();  // at least: near
  double far_disparity = -1.0;                                      // below: far
  int d_min = 0, d_max = 0;
};

// Each image's half of the preparation; the two halves run side by side (a pair matched as the
// capture goes on is the one the products wait for at the end).
void PrepareImage(const cv::Mat& rect, const PairMatchOptions& o, bool half, cv::Mat* lsm,
                  cv::Mat* searched, cv::Mat* half_lsm, ImageGradients* gradients,
                  ImageGradients* half_gradients) {
  EnhanceOptions smooth_only = o.enhance, wallis_only = o.enhance;
  smooth_only.wallis = false;
  wallis_only.gaussian_sigma_px = 0.0;
  *lsm = Enhance(rect, smooth_only);
  *searched = Enhance(*lsm, wallis_only);
  if (gradients) *gradients = ComputeGradients(*lsm);
  if (half) cv::pyrDown(*lsm, *half_lsm);
  if (half && half_gradients) *half_gradients = ComputeGradients(*half_lsm);
}

PairContext PreparePair(const Rectification& r, const cv::Mat& left_rect, const cv::Mat& right_rect,
                        const PairMatchOptions& o) {
  PairContext c;
  // (Without a known geometry, as for an explicit disparity range, there is no depth.)
  const bool explicit_range = o.max_disparity_px >= 0;
  const bool half = o.half_resolution_within_m > 0.0 && !explicit_range;
  cv::parallel_for_(
      cv::Range(0, 2),
      [&](const cv::Range& sides) {
        for (int side = sides.start; side < sides.end; ++side)
          if (side == 0)
            PrepareImage(left_rect, o, half, &c.lsm_left, &c.left, &c.half_left, &c.gradients,
                         &c.half_gradients);
          else
            PrepareImage(right_rect, o, half, &c.lsm_right, &c.right, &c.half_right, nullptr,
                         nullptr);
      },
      2.0);
  if (half) c.near_disparity = r.focal_px * r.baseline_m / o.half_resolution_within_m;
  c.half_lsm = o.near_lsm;
  c.half_lsm.max_sigma_px /= 2, c.half_lsm.max_shift_px /= 2, c.half_lsm.convergence_px /= 2;
  if (o.far_window_from_m > 0.0 && !explicit_range)
    c.far_disparity = r.focal_px * r.baseline_m / o.far_window_from_m;
  c.d_min = explicit_range ? o.min_disparity_px : r.MinDisparityPx(o.max_depth_m);
  c.d_max = explicit_range ? o.max_disparity_px : r.MaxDisparityPx(o.min_depth_m);
  return c;
}

// The full-resolution least-squares options at integer disparity d: far points get the wide,
// low windows.
const LsmOptions& FullResolutionLsm(const PairContext& c, const PairMatchOptions& o, int d) {
  return d < c.far_disparity ? o.far_lsm : o.lsm;
}

// Least squares from the integer disparity d: near points at half resolution (p even), far ones
// with the wide, low windows. Positions and sigmas in full-resolution pixels.
LsmResult FitSubPixel(const PairContext& c, const PairMatchOptions& o, cv::Point p, int d,
                      bool half, const Eigen::Matrix2d* shape) {
  if (!half)
    return MatchLsm(c.lsm_left, c.gradients, p, c.lsm_right, Eigen::Vector2d(p.x - d, p.y),
                    FullResolutionLsm(c, o, d), shape);
  LsmResult lsm = MatchLsm(c.half_left, c.half_gradients, p / 2, c.half_right,
                           Eigen::Vector2d(p.x - d, p.y) / 2, c.half_lsm, shape);
  lsm.position_px *= 2, lsm.sigma_x_px *= 2, lsm.sigma_y_px *= 2;
  return lsm;
}

// The least-squares window of a point, half its width and height in full-resolution pixels.
cv::Size LsmHalfWindow(const PairContext& c, const PairMatchOptions& o, int d, bool half) {
  const LsmOptions& w = half ? o.near_lsm : FullResolutionLsm(c, o, d);
  const int scale = half ? 2 : 1;
  return {scale * w.half_window_px,
          scale * (w.half_height_px > 0 ? w.half_height_px : w.half_window_px)};
}

// The share of a least-squares window that sees another surface. The pyramid's disparities
// over the window, in the left image and at the matched place in the right one, are compared
// with the window's own plane (its disparity and the fitted shear along the rows); of those
// departing by more than slack_px, the largest group within 2 slack_px of one another (one
// surface, not scattered noise) over all compared. Across an occlusion edge a window holds two
// surfaces and least squares blends them into the disparity of neither (a point in mid-air
// beside a brow); the two-way check passes such a point whenever the window's centre lies on
// one surface. (off_scratch: reused from point to point.)
double OtherSurfaceShare(const DisparityMap& left_map, const DisparityMap& right_map, cv::Point p,
                         double disparity, const LsmResult& lsm, cv::Size half_window,
                         double slack_px, std::vector<double>* off_scratch) {
  const int step = 1 << left_map.level;
  const double per_column = 1.0 - lsm.parameters[1], per_row = -lsm.parameters[2];
  int looked = 0;
  std::vector<double>& off = *off_scratch;
  off.clear();
  for (int y = -half_window.height; y <= half_window.height; y += step)
    for (int x = -half_window.width; x <= half_window.width; x += step) {
      const double plane = disparity + per_column * x + per_row * y;
      const int right_u = static_cast<int>(std::lround(p.x + x - plane));
      for (const int d : {MapDisparity(left_map, {p.x + x, p.y + y}),
                          MapDisparity(right_map, {right_u, p.y + y})}) {
        if (d < 0) continue;
        ++looked;
        if (std::abs(d - plane) > slack_px) off.push_back(d);
      }
    }
  if (looked == 0 || off.empty()) return 0.0;
  std::sort(off.begin(), off.end());
  size_t most = 0;
  for (size_t i = 0, j = 0; i < off.size(); ++i) {
    while (off[i] - off[j] > 2 * slack_px) ++j;
    most = std::max(most, i - j + 1);
  }
  return static_cast<double>(most) / looked;
}

// The matches whose least-squares residual is at most max_residual_ratio times the median of
// their neighbours' and of the pair's, the smaller, at the same resolution (half: matched at
// half resolution, where the noise per pixel is half).
std::vector<StereoMatch> KeepFittingMatches(std::vector<StereoMatch> matches,
                                            const std::vector<double>& residuals,
                                            const std::vector<uint8_t>& half, cv::Size image,
                                            const PairMatchOptions& o) {
  if (o.max_residual_ratio <= 0.0 || matches.empty()) return matches;
  const int square = o.residual_square_px;
  const int cols = image.width / square + 1, rows = image.height / square + 1;
  // Squares by resolution, row and column.
  auto bin = [&](int h, int r, int c) { return (static_cast<size_t>(h) * rows + r) * cols + c; };
  auto bin_of = [&](size_t i) {
    const int c = std::clamp(static_cast<int>(matches[i].left_px.x()) / square, 0, cols - 1);
    const int r = std::clamp(static_cast<int>(matches[i].left_px.y()) / square, 0, rows - 1);
    return bin(half[i], r, c);
  };
  std::vector<std::vector<double>> in_square(bin(2, 0, 0));
  for (size_t i = 0; i < matches.size(); ++i) in_square[bin_of(i)].push_back(residuals[i]);
  // The median over the 3 x 3 squares round each square that holds a match.
  std::vector<double> median(in_square.size(), 0.0), around;
  for (int h = 0; h < 2; ++h)
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        if (in_square[bin(h, r, c)].empty()) continue;
        around.clear();
        for (int rr = std::max(0, r - 1); rr <= std::min(rows - 1, r + 1); ++rr)
          for (int cc = std::max(0, c - 1); cc <= std::min(cols - 1, c + 1); ++cc) {
            const std::vector<double>& there = in_square[bin(h, rr, cc)];
            around.insert(around.end(), there.begin(), there.end());
          }
        median[bin(h, r, c)] = MedianInPlace(&around);
      }
  // The pair's median at each resolution: where a whole neighbourhood is blended (a slope
  // striped with lips, each window across one), its median is the blends' own.
  double pair_median[2] = {0.0, 0.0};
  for (int h = 0; h < 2; ++h) {
    around.clear();
    for (size_t i = 0; i < matches.size(); ++i)
      if (half[i] == h) around.push_back(residuals[i]);
    pair_median[h] = MedianInPlace(&around);
  }
  size_t kept = 0;
  for (size_t i = 0; i < matches.size(); ++i)
    if (residuals[i] <= o.max_residual_ratio * std::min(median[bin_of(i)], pair_median[half[i]]))
      matches[kept++] = matches[i];
  matches.resize(kept);
  return matches;
}

}  // namespace

std::vector<StereoMatch> MatchRectifiedPair(const Rectification& r, const cv::Mat& left_rect,
                                            const cv::Mat& right_rect, const PairMatchOptions& o,
                                            PairMatchSummary* summary) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("pair matching: " + why);
  PairMatchSummary s;
  auto clock = std::chrono::steady_clock::now();
  const PairContext c = PreparePair(r, left_rect, right_rect, o);
  s.enhance_s = SecondsSince(&clock);

  // Approximations for both images (the right one as the mirror image of the problem) and the
  // interest points, side by side.
  DisparityMap left_map, right_map;
  std::vector<cv::Point> points;
  cv::parallel_for_(
      cv::Range(0, 3),
      [&](const cv::Range& tasks) {
        for (int task = tasks.start; task < tasks.end; ++task) {
          if (task == 0) {
            left_map =
                MatchPyramid(c.left, c.right, c.d_min, c.d_max, o.dense_finest_level, o.pyramid);
          } else if (task == 1) {
            cv::Mat left_flipped, right_flipped;
            cv::flip(c.left, left_flipped, 1);
            cv::flip(c.right, right_flipped, 1);
            right_map = MatchPyramid(right_flipped, left_flipped, c.d_min, c.d_max,
                                     o.dense_finest_level, o.pyramid);
            cv::flip(right_map.disparity, right_map.disparity, 1);
            // Flipping a map of odd width shifts its pixels by one level-pixel against the image;
            // the full-resolution search's radius absorbs it.
          } else {
            points = Points(c.left, o);
          }
        }
      },
      3.0);
  s.maps_and_points_s = SecondsSince(&clock);
  s.points = static_cast<int>(points.size());
  const int h = o.ncc_half_window_px;
  std::vector<StereoMatch> matches;
  matches.reserve(points.size() / 2);
  SpacingFilter spacing(o.min_spacing_m, r.baseline_m, r.focal_px);
  bool have_last = false;
  cv::Point last;
  int last_d = 0;
  Eigen::Matrix2d last_shape;
  std::unordered_set<int64_t> half_taken;  // near points snapped to one even pixel: once
  std::vector<double> off_surface, residuals;
  std::vector<uint8_t> matched_at_half;
  for (cv::Point p : points) {
    // The pyramid's disparity: for the spacing and for near or far.
    const int approx = MapDisparity(left_map, p);
    if (o.min_spacing_m > 0.0 && (approx < 0 || !spacing.Free(p.x, p.y, approx))) continue;
    const bool half = approx >= c.near_disparity;
    if (half) {
      p = cv::Point(2 * ((p.x + 1) / 2), 2 * ((p.y + 1) / 2));
      if (!half_taken.insert((static_cast<int64_t>(p.y) << 32) | p.x).second) continue;
    }
    double ncc = 0.0;
    const int d = RefineFromMap(left_map, c.left, c.right, p.x, p.y, c.d_min, c.d_max, h, +1, &ncc);
    if (d < 0 || ncc < o.min_ncc) continue;
    ++s.ncc_accepted;
    // Two-way: the right image's own search, from the matched position, must come home; first
    // at the integer match (least squares only for points that do), then at the sub-pixel one.
    double back_ncc = 0.0;
    const int back =
        RefineFromMap(right_map, c.right, c.left, p.x - d, p.y, c.d_min, c.d_max, h, -1, &back_ncc);
    if (back < 0 || back_ncc < o.min_ncc || std::abs(back - d) > o.max_consistency_px) continue;
    // The last fit's shape where it is a neighbour on the same surface (points come in image
    // order): on slanted ground it saves the iterations that would find the shear.
    const bool neighbour = have_last && p.y - last.y <= h &&
                           p.x - last.x <= 4 * o.lsm.half_window_px && std::abs(d - last_d) <= 2;
    const LsmResult lsm = FitSubPixel(c, o, p, d, half, neighbour ? &last_shape : nullptr);
    if (!lsm.ok) continue;
    have_last = true, last = p, last_d = d;
    last_shape << lsm.parameters[1], lsm.parameters[2], lsm.parameters[4], lsm.parameters[5];
    ++s.lsm_accepted;
    const double disparity = p.x - lsm.position_px.x();
    if (std::abs(back - disparity) > o.max_consistency_px + 0.5) continue;
    ++s.consistent;
    const cv::Size half_window = LsmHalfWindow(c, o, d, half);
    if (o.max_other_surface_share < 1.0 &&
        OtherSurfaceShare(left_map, right_map, p, disparity, lsm, half_window,
                          o.max_consistency_px + (1 << left_map.level),
                          &off_surface) > o.max_other_surface_share)
      continue;
    ++s.one_surface;
    if (o.min_spacing_m > 0.0) spacing.Take(p.x, p.y, approx);
    matches.push_back({Eigen::Vector2d(p.x, p.y), lsm.position_px, disparity,
                       o.sigma_scale * lsm.sigma_x_px, lsm.correlation,
                       Eigen::Vector2d(half_window.width, half_window.height)});
    residuals.push_back(lsm.sigma0);
    matched_at_half.push_back(half);
  }
  matches = KeepFittingMatches(std::move(matches), residuals, matched_at_half, left_rect.size(), o);
  s.fitting = static_cast<int>(matches.size());
  s.matching_s = SecondsSince(&clock);
  if (summary) *summary = s;
  return matches;
}

}  // namespace ts
