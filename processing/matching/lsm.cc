#include "processing/matching/lsm.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <vector>

namespace ts {

bool LsmOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (half_height_px == 1) err = "half_height_px must be 0 (square) or in [2, 50]";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

ImageGradients ComputeGradients(const cv::Mat& image) {
  ImageGradients g;
  g.dx = cv::Mat::zeros(image.size(), CV_32FC1);
  g.dy = cv::Mat::zeros(image.size(), CV_32FC1);
  for (int y = 1; y + 1 < image.rows; ++y) {
    const float* up = image.ptr<float>(y - 1);
    const float* row = image.ptr<float>(y);
    const float* down = image.ptr<float>(y + 1);
    float* dx = g.dx.ptr<float>(y);
    float* dy = g.dy.ptr<float>(y);
    for (int x = 1; x + 1 < image.cols; ++x) {
      dx[x] = 0.5f * (row[x + 1] - row[x - 1]);
      dy[x] = 0.5f * (down[x] - up[x]);
    }
  }
  return g;
}

namespace {

// out[i] = row linearly interpolated at x + i dx, i < count (all positions >= 0 and inside).
// Four samples at a time (OpenCV's universal intrinsics: SSE, NEON); when the four fall on
// consecutive pixels, as they mostly do with dx near 1, from two plain loads instead of a
// gather.
void RowSamples(const float* row, float x, float dx, int count, float* out) {
  int i = 0;
#if CV_SIMD128
  const cv::v_float32x4 offsets = cv::v_float32x4(0.0f, 1.0f, 2.0f, 3.0f) * cv::v_setall_f32(dx);
  alignas(16) int index[4];
  for (; i + 4 <= count; i += 4) {
    const cv::v_float32x4 xs = cv::v_setall_f32(x + static_cast<float>(i) * dx) + offsets;
    const cv::v_int32x4 x0 = cv::v_trunc(xs);
    const cv::v_float32x4 t = xs - cv::v_cvt_f32(x0);
    cv::v_store_aligned(index, x0);
    cv::v_float32x4 a, b;
    if (index[3] - index[0] == 3) {
      a = cv::v_load(row + index[0]);
      b = cv::v_load(row + index[0] + 1);
    } else {
      a = cv::v_lut(row, x0);
      b = cv::v_lut(row + 1, x0);
    }
    cv::v_store(out + i, cv::v_fma(t, b - a, a));
  }
#endif
  for (; i < count; ++i) {
    const float xs = x + static_cast<float>(i) * dx;
    const int x0 = static_cast<int>(xs);
    const float t = xs - static_cast<float>(x0);
    out[i] = row[x0] + t * (row[x0 + 1] - row[x0]);
  }
}

// Resamples the search window under the affine warp (search = A [x y 1]^T); false if any
// sample falls outside the image. Along rows only (A's second row is [0 1 y]): every sample of
// a row lies on one image row, so the interpolation is linear, not bilinear.
template <bool kAlongRows>
bool Warp(const cv::Mat& search, const Eigen::Matrix<double, 2, 3>& a, int hx, int hy, float* out) {
  // Corners first: the affine image of the window is inside if its corners are.
  for (const int cy : {-hy, hy})
    for (const int cx : {-hx, hx}) {
      const double xs = a(0, 0) * cx + a(0, 1) * cy + a(0, 2);
      const double ys = a(1, 0) * cx + a(1, 1) * cy + a(1, 2);
      if (!(xs >= 0.0 && ys >= 0.0 && xs < search.cols - 1 && ys < search.rows - 1)) return false;
    }
  const size_t step = search.step1();
  const float* data = search.ptr<float>();
  const float dxx = static_cast<float>(a(0, 0)), dyx = static_cast<float>(a(1, 0));
  const float* centre_row = data + static_cast<ptrdiff_t>(std::lround(a(1, 2))) * step;
  int k = 0;
  for (int y = -hy; y <= hy; ++y) {
    float xs = static_cast<float>(a(0, 0) * -hx + a(0, 1) * y + a(0, 2));
    if constexpr (kAlongRows) {
      RowSamples(centre_row + static_cast<ptrdiff_t>(y) * step, xs, dxx, 2 * hx + 1, out + k);
      k += 2 * hx + 1;
    } else {
      float ys = static_cast<float>(a(1, 0) * -hx + a(1, 1) * y + a(1, 2));
      for (int x = -hx; x <= hx; ++x, ++k, xs += dxx, ys += dyx) {
        const int x0 = static_cast<int>(xs), y0 = static_cast<int>(ys);  // both >= 0
        const float tx = xs - x0, ty = ys - y0;
        const float* r0 = data + y0 * step + x0;
        const float* r1 = r0 + step;
        out[k] = r0[0] + tx * (r0[1] - r0[0]) +
                 ty * (r1[0] - r0[0] + tx * (r1[1] - r1[0] - r0[1] + r0[0]));
      }
    }
  }
  return true;
}

// Sums over a window, four lanes at a time where there are SIMD registers (OpenCV's universal
// intrinsics), one at a time otherwise; the lanes are added up in double at the end.
#if CV_SIMD128
using Lane = cv::v_float32x4;
constexpr int kLanes = 4;
inline Lane LoadLane(const float* p) { return cv::v_load(p); }
inline Lane SplatLane(float v) { return cv::v_setall_f32(v); }
inline double LaneSum(const Lane& v) { return cv::v_reduce_sum(v); }
inline void StoreLane(float* p, const Lane& v) { cv::v_store(p, v); }
#else
using Lane = float;
constexpr int kLanes = 1;
inline Lane LoadLane(const float* p) { return *p; }
inline void StoreLane(float* p, Lane v) { *p = v; }
inline Lane SplatLane(float v) { return v; }
inline double LaneSum(Lane v) { return v; }
#endif

// Copies w floats a lane at a time (no library call for these short rows). The last lane may
// read and write up to kLanes - 1 floats past the row: the caller leaves room for them.
inline void CopyRow(const float* from, int w, float* to) {
  for (int i = 0; i < w; i += kLanes) StoreLane(to + i, LoadLane(from + i));
}

// The geometric Jacobian's columns are the template's gradients times (1, x, y): column
// 3a + p is gradient a (d/dx; d/dy for the full affine fit) times weight p (1, x or y).
// Its products with itself are sums of gradient products times (1, x, y, x^2, xy, y^2),
// indexed by the pair of weights:
constexpr int WeightPair(int p, int q) {
  return p > q ? WeightPair(q, p) : p == 0 ? q : p == 1 ? 2 + q : 5;
}

// The template's sums that least squares needs, over the window, from one pass over its
// centred grey values f, gradients and pixel coordinates (no Jacobian is stored):
template <int B>  // gradient images: 1 (d/dx) or 2 (d/dx, d/dy)
struct TemplateSums {
  double ff = 0.0;                     // f.f
  double g[B][3] = {};                 // sum of gradient a times (1, x, y): the columns' sums
  double gf[B][3] = {};                // the same times f: the columns' products with f
  double gg[B * (B + 1) / 2][6] = {};  // gradient products (a <= b) times WeightPair weights
};

template <int B>
TemplateSums<B> SumTemplate(const float* f, const float* const* grad, const float* wx,
                            const float* wy, int padded) {
  constexpr int kPairs = B * (B + 1) / 2;
  const Lane zero = SplatLane(0.0f);
  Lane ff = zero, g[B][3], gf[B][3], gg[kPairs][6];
  for (auto& row : g) std::fill(row, row + 3, zero);
  for (auto& row : gf) std::fill(row, row + 3, zero);
  for (auto& row : gg) std::fill(row, row + 6, zero);
  for (int i = 0; i < padded; i += kLanes) {
    const Lane fv = LoadLane(f + i), xv = LoadLane(wx + i), yv = LoadLane(wy + i);
    ff += fv * fv;
    Lane gv[B];
    for (int a = 0; a < B; ++a) {
      gv[a] = LoadLane(grad[a] + i);
      const Lane gfv = gv[a] * fv;
      g[a][0] += gv[a], g[a][1] += gv[a] * xv, g[a][2] += gv[a] * yv;
      gf[a][0] += gfv, gf[a][1] += gfv * xv, gf[a][2] += gfv * yv;
    }
    for (int a = 0, k = 0; a < B; ++a)
      for (int b = a; b < B; ++b, ++k) {
        const Lane h = gv[a] * gv[b], hx = h * xv, hy = h * yv;
        gg[k][0] += h, gg[k][1] += hx, gg[k][2] += hy;
        gg[k][3] += hx * xv, gg[k][4] += hx * yv, gg[k][5] += hy * yv;
      }
  }
  TemplateSums<B> s;
  s.ff = LaneSum(ff);
  for (int a = 0; a < B; ++a)
    for (int p = 0; p < 3; ++p) s.g[a][p] = LaneSum(g[a][p]), s.gf[a][p] = LaneSum(gf[a][p]);
  for (int k = 0; k < kPairs; ++k)
    for (int w = 0; w < 6; ++w) s.gg[k][w] = LaneSum(gg[k][w]);
  return s;
}

// One iteration's sums of the resampled window g, shifted by c (the template's mean, against
// cancellation; the padding holds c): sum, squares, product with f, and the products with the
// Jacobian's raw columns (gradient a times weight p).
template <int B>
struct WindowSums {
  double g = 0.0, gg = 0.0, fg = 0.0;
  double raw[B][3] = {};
};

template <int B>
WindowSums<B> SumWindow(const float* g, float c, const float* f, const float* const* grad,
                        const float* wx, const float* wy, int padded) {
  const Lane zero = SplatLane(0.0f), shift = SplatLane(c);
  Lane sg = zero, sgg = zero, sfg = zero, raw[B][3];
  for (auto& row : raw) std::fill(row, row + 3, zero);
  for (int i = 0; i < padded; i += kLanes) {
    const Lane gv = LoadLane(g + i) - shift, xv = LoadLane(wx + i), yv = LoadLane(wy + i);
    sg += gv, sgg += gv * gv, sfg += LoadLane(f + i) * gv;
    for (int a = 0; a < B; ++a) {
      const Lane t = LoadLane(grad[a] + i) * gv;
      raw[a][0] += t, raw[a][1] += t * xv, raw[a][2] += t * yv;
    }
  }
  WindowSums<B> s;
  s.g = LaneSum(sg), s.gg = LaneSum(sgg), s.fg = LaneSum(sfg);
  for (int a = 0; a < B; ++a)
    for (int p = 0; p < 3; ++p) s.raw[a][p] = LaneSum(raw[a][p]);
  return s;
}

// K geometric parameters: 6 (a0 a1 a2 b0 b1 b2) or 3 (a0 a1 a2: along rows only).
template <int K>
LsmResult Solve(const cv::Mat& templ, const ImageGradients& tg, const cv::Point& centre,
                const cv::Mat& search, const Eigen::Vector2d& start, const LsmOptions& o,
                const Eigen::Matrix2d* start_shape) {
  using MatrixK = Eigen::Matrix<double, K, K>;
  using VectorK = Eigen::Matrix<double, K, 1>;
  constexpr bool kAlongRows = K == 3;
  constexpr int B = K / 3;
  LsmResult result;
  const int hx = o.half_window_px, hy = o.half_height_px > 0 ? o.half_height_px : hx;
  const int w = 2 * hx + 1, n = w * (2 * hy + 1);
  const int padded = (n + kLanes - 1) / kLanes * kLanes;
  if (centre.x - hx < 1 || centre.y - hy < 1 || centre.x + hx + 1 >= templ.cols ||
      centre.y + hy + 1 >= templ.rows) {
    result.why = "template window leaves the image";
    return result;
  }
  // Per-thread scratch, `padded` long each (and a lane more, for CopyRow): the template's
  // grey values (then centred), the resampled search window, the pixel coordinates (x, y)
  // relative to the centre, and the template's gradients. The template's padding is zero, so
  // it adds nothing to any sum. (The template rows CopyRow reads past the window exist: the
  // window stays a pixel inside the image.)
  const int stride = padded + kLanes;
  thread_local std::vector<float> buffer;
  thread_local int coordinates_for = -1;  // (hx, hy) the coordinates were written for
  buffer.resize((B + 4) * static_cast<size_t>(stride));
  float* f = buffer.data();
  float* g = f + stride;
  float* wx = g + stride;
  float* wy = wx + stride;
  float* grad[B];
  for (int a = 0; a < B; ++a) grad[a] = wy + (a + 1) * stride;
  if (coordinates_for != (hx << 16 | hy)) {
    coordinates_for = hx << 16 | hy;
    std::fill(wx, wx + 2 * stride, 0.0f);
    for (int y = -hy, k = 0; y <= hy; ++y)
      for (int x = -hx; x <= hx; ++x, ++k)
        wx[k] = static_cast<float>(x), wy[k] = static_cast<float>(y);
  }
  const cv::Mat* sources[2] = {&tg.dx, &tg.dy};
  for (int y = -hy, k = 0; y <= hy; ++y, k += w) {
    CopyRow(templ.ptr<float>(centre.y + y) + centre.x - hx, w, f + k);
    for (int a = 0; a < B; ++a)
      CopyRow(sources[a]->ptr<float>(centre.y + y) + centre.x - hx, w, grad[a] + k);
  }
  std::fill(f + n, f + padded, 0.0f);
  for (int a = 0; a < B; ++a) std::fill(grad[a] + n, grad[a] + padded, 0.0f);
  using MapVector = Eigen::Map<Eigen::VectorXf>;
  MapVector fv(f, n);
  const double mean_f = static_cast<double>(fv.sum()) / n;
  fv.array() -= static_cast<float>(mean_f);
  const TemplateSums<B> ts = SumTemplate<B>(f, grad, wx, wy, padded);
  const double var_f = ts.ff;  // n x variance
  if (!(var_f > 1e-6 * n)) {
    result.why = "no texture: template is flat";
    return result;
  }
  // The radiometric directions (a constant and the template itself) are projected out of the
  // geometric Jacobian: the geometry is then estimated independently of brightness and
  // contrast. With 1 and f orthogonal (f is centred), a projected column is
  //   J_j = s_j - (sum s_j / n) 1 - (s_j.f / f.f) f
  // for its raw column s_j, and the normal matrix is the raw products less the projections'.
  auto column_sum = [&](int j) { return ts.g[j / 3][j % 3]; };
  auto column_f = [&](int j) { return ts.gf[j / 3][j % 3]; };
  MatrixK normal;
  for (int j = 0; j < K; ++j)
    for (int k = j; k < K; ++k) {
      const int a = j / 3, b = k / 3, pair = a * B - a * (a - 1) / 2 + (b - a);
      normal(j, k) = normal(k, j) = ts.gg[pair][WeightPair(j % 3, k % 3)] -
                                    column_sum(j) * column_sum(k) / n -
                                    column_f(j) * column_f(k) / var_f;
    }
  const Eigen::LDLT<MatrixK> ldlt(normal);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      !(ldlt.vectorD().minCoeff() > 1e-9 * ldlt.vectorD().maxCoeff())) {
    result.why = "no texture: normal equations singular";
    return result;
  }
  // Constant over the iterations (the inverse-compositional form): solve once.
  const MatrixK inverse = ldlt.solve(MatrixK::Identity());

  Eigen::Matrix3d warp = Eigen::Matrix3d::Identity();  // search = warp * [x y 1]
  if (start_shape) warp.topLeftCorner<2, 2>() = *start_shape;
  if constexpr (kAlongRows) warp.block<1, 2>(1, 0) << 0.0, 1.0;
  warp(0, 2) = start.x();
  warp(1, 2) = kAlongRows ? std::round(start.y()) : start.y();
  const Eigen::RowVector3d fixed_row = warp.row(1);  // along rows: never changes
  for (result.iterations = 1; result.iterations <= o.max_iterations; ++result.iterations) {
    if (!Warp<kAlongRows>(search, warp.topRows<2>(), hx, hy, g)) {
      result.why = "search window leaves the image";
      return result;
    }
    std::fill(g + n, g + padded, static_cast<float>(mean_f));  // adds nothing once shifted
    const WindowSums<B> ws = SumWindow<B>(g, static_cast<float>(mean_f), f, grad, wx, wy, padded);
    const double sfg = ws.fg, sg = ws.g + n * mean_f;
    const double var_g = ws.gg - ws.g * ws.g / n;  // n times the variance
    if (!(var_g > 1e-6 * n)) {
      result.why = "no texture: search window is flat";
      return result;
    }
    // Radiometry in closed form, f ~ r0 + r1 g; the residual r0 + r1 g - f is orthogonal to the
    // projected columns but for r1 g, so its product with them is r1 times J^T g.
    const double r1 = sfg / var_g, r0 = mean_f - r1 * sg / n;
    VectorK rhs;
    for (int j = 0; j < K; ++j)
      rhs[j] = r1 * (ws.raw[j / 3][j % 3] - column_sum(j) * ws.g / n - column_f(j) * sfg / var_f);
    const VectorK dp = inverse * rhs;
    if (!dp.allFinite()) {
      result.why = "no texture: normal equations singular";
      return result;
    }
    Eigen::Matrix3d inc = Eigen::Matrix3d::Identity();
    inc.row(0) << 1 + dp[1], dp[2], dp[0];
    if constexpr (!kAlongRows) inc.row(1) << dp[4], 1 + dp[5], dp[3];
    const Eigen::Vector2d before = warp.block<2, 1>(0, 2);
    warp = warp * inc.inverse();
    if constexpr (kAlongRows) warp.row(1) = fixed_row;  // exactly, not as an inverse gives it
    const Eigen::Vector2d position = warp.block<2, 1>(0, 2);
    if ((position - start).norm() > o.max_shift_px) {
      result.why = "moved more than max_shift_px from the start";
      return result;
    }
    if ((position - before).norm() >= o.convergence_px) continue;
    // Converged. Residual sum of squares of the fitted windows, from the sums; the increment
    // was in template coordinates, the position moves by the warp's linear part times it.
    const double sum_v2 = std::max(0.0, var_f - r1 * sfg);
    const double sigma0_sq = sum_v2 / (n - K - 2);
    Eigen::Matrix2d template_cov = Eigen::Matrix2d::Zero();  // of (a0, b0)
    if constexpr (kAlongRows)
      template_cov(0, 0) = inverse(0, 0);
    else
      template_cov << inverse(0, 0), inverse(0, 3), inverse(3, 0), inverse(3, 3);
    const Eigen::Matrix2d linear = warp.topLeftCorner<2, 2>();
    const Eigen::Matrix2d cov = sigma0_sq * linear * template_cov * linear.transpose();
    result.position_px = position;
    result.parameters << warp(0, 2), warp(0, 0), warp(0, 1), warp(1, 2), warp(1, 0), warp(1, 1), r0,
        r1;
    result.sigma0 = std::sqrt(sigma0_sq);
    result.sigma_x_px = std::sqrt(cov(0, 0));
    result.sigma_y_px = std::sqrt(cov(1, 1));
    result.correlation = sfg / std::sqrt(var_g * var_f);
    if (result.correlation < o.min_correlation) {
      result.why = "correlation below min_correlation";
    } else if (std::max(result.sigma_x_px, result.sigma_y_px) > o.max_sigma_px) {
      result.why = "sigma above max_sigma_px";
    } else {
      result.ok = true;
    }
    return result;
  }
  result.why = "did not converge";
  return result;
}

}  // namespace

LsmResult MatchLsm(const cv::Mat& templ, const ImageGradients& tg, const cv::Point& centre,
                   const cv::Mat& search, const Eigen::Vector2d& start, const LsmOptions& o,
                   const Eigen::Matrix2d* start_shape) {
  LsmResult result;
  if (!o.Check(&result.why)) return result;
  return o.along_rows_only ? Solve<3>(templ, tg, centre, search, start, o, start_shape)
                           : Solve<6>(templ, tg, centre, search, start, o, start_shape);
}

}  // namespace ts
