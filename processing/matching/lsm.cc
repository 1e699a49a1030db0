#include "processing/matching/lsm.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <vector>

namespace ts {

bool LsmOptions::Check(std::string* why) const {
  std::string err;
  if (half_window_px < 2 || half_window_px > 50)
    err = "half_window_px must be in [2, 50]";
  else if (half_height_px < 0 || half_height_px > 50 || half_height_px == 1)
    err = "half_height_px must be 0 (square) or in [2, 50]";
  else if (max_iterations < 1)
    err = "max_iterations must be at least 1";
  else if (!(convergence_px > 0.0) || !(max_shift_px > 0.0) || !(max_sigma_px > 0.0))
    err = "convergence, max shift and max sigma must be positive";
  else if (!(min_correlation >= -1.0 && min_correlation <= 1.0))
    err = "min_correlation must be in [-1, 1]";
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

// K geometric parameters: 6 (a0 a1 a2 b0 b1 b2) or 3 (a0 a1 a2: along rows only).
template <int K>
LsmResult Solve(const cv::Mat& templ, const ImageGradients& tg, const cv::Point& centre,
                const cv::Mat& search, const Eigen::Vector2d& start, const LsmOptions& o,
                const Eigen::Matrix2d* start_shape) {
  using MatrixK = Eigen::Matrix<double, K, K>;
  using VectorK = Eigen::Matrix<double, K, 1>;
  constexpr bool kAlongRows = K == 3;
  LsmResult result;
  const int hx = o.half_window_px, hy = o.half_height_px > 0 ? o.half_height_px : hx;
  const int n = (2 * hx + 1) * (2 * hy + 1);
  if (centre.x - hx < 1 || centre.y - hy < 1 || centre.x + hx + 1 >= templ.cols ||
      centre.y + hy + 1 >= templ.rows) {
    result.why = "template window leaves the image";
    return result;
  }
  // Per-thread scratch, side by side: the steepest-descent images d f / d(a0 a1 a2 [b0 b1 b2])
  // at the identity warp, the centred template, ones, and the resampled search window. One
  // matrix-vector product per iteration then gives all the sums of the resampled window: its
  // products with the K columns, with the template, and with ones.
  thread_local std::vector<float> buffer;
  buffer.resize((K + 3) * static_cast<size_t>(n));
  float* sd[K];
  for (int j = 0; j < K; ++j) sd[j] = buffer.data() + j * n;
  float* f = buffer.data() + K * n;
  float* ones = f + n;
  float* g = ones + n;
  std::fill(ones, ones + n, 1.0f);
  const int w = 2 * hx + 1;
  for (int y = -hy, k = 0; y <= hy; ++y, k += w) {
    const float* fr = templ.ptr<float>(centre.y + y) + centre.x - hx;
    const float* gx = tg.dx.ptr<float>(centre.y + y) + centre.x - hx;
    const float* gy = tg.dy.ptr<float>(centre.y + y) + centre.x - hx;
    for (int i = 0; i < w; ++i) {
      const float x = static_cast<float>(i - hx);
      f[k + i] = fr[i];
      sd[0][k + i] = gx[i], sd[1][k + i] = gx[i] * x, sd[2][k + i] = gx[i] * y;
      if constexpr (!kAlongRows)
        sd[3][k + i] = gy[i], sd[4][k + i] = gy[i] * x, sd[5][k + i] = gy[i] * y;
    }
  }
  const double mean_f = static_cast<double>(Eigen::Map<Eigen::VectorXf>(f, n).sum()) / n;
  Eigen::Map<Eigen::VectorXf>(f, n).array() -= static_cast<float>(mean_f);
  const double var_f = Eigen::Map<Eigen::VectorXf>(f, n).squaredNorm();  // n x variance
  if (!(var_f > 1e-6 * n)) {
    result.why = "no texture: template is flat";
    return result;
  }
  // Project the radiometric directions (a constant and the template itself) out of the
  // geometric Jacobian: the geometry is then estimated independently of brightness and
  // contrast, and since every column is orthogonal to both, its product with the residual
  // r0 + r1 g - f reduces to r1 times its product with g.
  // (Eigen maps: vectorised sums with independent accumulators.)
  using MapVector = Eigen::Map<Eigen::VectorXf>;
  const MapVector fv(f, n), gv(g, n);
  Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, K>> jacobian(sd[0], n, K);
  const Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, K + 2>> sums(sd[0], n, K + 2);
  for (int j = 0; j < K; ++j) {
    auto column = jacobian.col(j);
    const float mean = column.mean(), along = static_cast<float>(column.dot(fv) / var_f);
    column.array() -= mean + along * fv.array();
  }
  Eigen::Matrix<float, K, K> normal_f;  // vectorised dot products, no GEMM blocking
  normal_f.noalias() = jacobian.transpose().lazyProduct(jacobian);
  const MatrixK normal = normal_f.template cast<double>();
  const Eigen::LDLT<MatrixK> ldlt(normal);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      !(ldlt.vectorD().minCoeff() > 1e-9 * ldlt.vectorD().maxCoeff())) {
    result.why = "no texture: normal equations singular";
    return result;
  }

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
    const Eigen::Matrix<float, K + 2, 1> dots = sums.transpose() * gv;  // J^T g, f.g, sum g
    const double sfg = dots[K], sg = dots[K + 1], sgg = gv.squaredNorm();
    const double var_g = sgg - sg * sg / n;  // n times the variance
    if (!(var_g > 1e-6 * n)) {
      result.why = "no texture: search window is flat";
      return result;
    }
    // Radiometry in closed form, f ~ r0 + r1 g; the residual's product with the Jacobian.
    const double r1 = sfg / var_g, r0 = mean_f - r1 * sg / n;
    VectorK rhs;
    for (int j = 0; j < K; ++j) rhs[j] = r1 * dots[j];
    const VectorK dp = ldlt.solve(rhs);
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
    const MatrixK inverse = ldlt.solve(MatrixK::Identity());
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
