#include "processing/matching/pyramid_ncc.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace ts {

bool PyramidNccOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

namespace {

cv::Mat Box(const cv::Mat& m, int h) {
  cv::Mat out;
  cv::boxFilter(m, out, -1, cv::Size(2 * h + 1, 2 * h + 1), cv::Point(-1, -1), false,
                cv::BORDER_REPLICATE);
  return out;
}

// Window sums of one image, for NCC with many partners.
struct WindowStats {
  cv::Mat sum, variance;  // sum and n * variance over the window
};
WindowStats Stats(const cv::Mat& image, int h) {
  const double n = (2 * h + 1) * (2 * h + 1);
  WindowStats s;
  s.sum = Box(image, h);
  s.variance = Box(image.mul(image), h) - s.sum.mul(s.sum) / n;
  return s;
}

// Full search of [d_min, d_max] for every pixel.
void SearchAll(const cv::Mat& left_image, const cv::Mat& right_image, int d_min, int d_max, int h,
               cv::Mat* disparity_out, cv::Mat* score_out) {
  // Both images go on h columns past their right edge (replicated), so that the windows of the
  // last columns are whole; the maps are cut back to the image at the end.
  cv::Mat left, right;
  cv::copyMakeBorder(left_image, left, 0, 0, 0, h, cv::BORDER_REPLICATE);
  cv::copyMakeBorder(right_image, right, 0, 0, 0, h, cv::BORDER_REPLICATE);
  cv::Mat padded_disparity, padded_score;
  cv::Mat* disparity = &padded_disparity;
  cv::Mat* score = &padded_score;
  const float n = static_cast<float>((2 * h + 1) * (2 * h + 1));
  const WindowStats ls = Stats(left, h), rs = Stats(right, h);
  disparity->create(left.size(), CV_16SC1);
  disparity->setTo(-1);
  score->create(left.size(), CV_32FC1);
  score->setTo(-2.0f);
  cv::Mat product(left.size(), CV_32FC1);
  // Only windows wholly inside both images are scored.
  for (int d = d_min; d <= d_max && d < left.cols; ++d) {
    product.setTo(0.0f);
    for (int y = 0; y < left.rows; ++y) {
      const float* l = left.ptr<float>(y);
      const float* r = right.ptr<float>(y);
      float* p = product.ptr<float>(y);
      for (int x = d; x < left.cols; ++x) p[x] = l[x] * r[x - d];
    }
    const cv::Mat sums = Box(product, h);
    for (int y = 0; y < left.rows; ++y) {
      const float* sp = sums.ptr<float>(y);
      const float* sl = ls.sum.ptr<float>(y);
      const float* vl = ls.variance.ptr<float>(y);
      const float* sr = rs.sum.ptr<float>(y);
      const float* vr = rs.variance.ptr<float>(y);
      float* best = score->ptr<float>(y);
      int16_t* disp = disparity->ptr<int16_t>(y);
      for (int x = d + h; x + h < left.cols; ++x) {
        const float var = vl[x] * vr[x - d];
        if (!(var > 1e-3f)) continue;
        const float ncc = (sp[x] - sl[x] * sr[x - d] / n) / std::sqrt(var);
        if (ncc > best[x]) best[x] = ncc, disp[x] = static_cast<int16_t>(d);
      }
    }
  }
  const cv::Rect image(0, 0, left_image.cols, left_image.rows);
  padded_disparity(image).copyTo(*disparity_out);
  padded_score(image).copyTo(*score_out);
}

// One row of Refine's scores for offset k: sums holds per pixel the window sums of the
// gathered right pixels, their squares, their products with the left ones and the count of
// those inside. Where the NCC beats best, best and disparity (hypothesis + k) take it. Four
// pixels at a time where there are SIMD registers.
void ScoreRow(const float* sums, const float* left_sum, const float* left_variance,
              const int16_t* hypothesis, int k, float n, int cols, float* best,
              int16_t* disparity) {
  int x = 0;
#if CV_SIMD128
  const cv::v_float32x4 inv_n = cv::v_setall_f32(1.0f / n), whole = cv::v_setall_f32(n - 0.5f),
                        min_var = cv::v_setall_f32(1e-3f);
  for (; x + 4 <= cols; x += 4) {
    cv::v_float32x4 sr, srr, slr, count;
    cv::v_load_deinterleave(sums + 4 * x, sr, srr, slr, count);
    const cv::v_float32x4 var = cv::v_load(left_variance + x) * (srr - sr * sr * inv_n);
    const cv::v_float32x4 ncc =
        (slr - cv::v_load(left_sum + x) * sr * inv_n) / cv::v_sqrt(cv::v_max(var, min_var));
    const cv::v_float32x4 old_best = cv::v_load(best + x);
    const cv::v_float32x4 better = (count > whole) & (var > min_var) & (ncc > old_best);
    if (cv::v_check_any(better)) {
      cv::v_store(best + x, cv::v_select(better, ncc, old_best));
      alignas(16) int take[4];
      cv::v_store_aligned(take, cv::v_reinterpret_as_s32(better));
      for (int i = 0; i < 4; ++i)
        if (take[i]) disparity[x + i] = static_cast<int16_t>(hypothesis[x + i] + k);
    }
  }
#endif
  for (; x < cols; ++x) {
    const float sr = sums[4 * x], var = left_variance[x] * (sums[4 * x + 1] - sr * sr / n);
    if (sums[4 * x + 3] < n - 0.5f || !(var > 1e-3f)) continue;  // a window partly outside
    const float ncc = (sums[4 * x + 2] - left_sum[x] * sr / n) / std::sqrt(var);
    if (ncc > best[x]) best[x] = ncc, disparity[x] = static_cast<int16_t>(hypothesis[x] + k);
  }
}

// Refinement of per-pixel hypotheses by +-radius, each window under its pixels' own
// hypotheses (see the header). Per offset k, the four window sums a score needs (the right
// pixels gathered under the hypotheses, their squares, their products with the left pixels,
// and how many were inside) come from one box filter over four channels.
void Refine(const cv::Mat& left, const cv::Mat& right, const cv::Mat& hypothesis, int d_min,
            int d_max, int h, int radius, cv::Mat* disparity, cv::Mat* score) {
  const float n = static_cast<float>((2 * h + 1) * (2 * h + 1));
  const WindowStats ls = Stats(left, h);
  disparity->create(left.size(), CV_16SC1);
  disparity->setTo(-1);
  score->create(left.size(), CV_32FC1);
  score->setTo(-2.0f);
  cv::Mat gathered(left.size(), CV_32FC4), sums;
  for (int k = -radius; k <= radius; ++k) {
    for (int y = 0; y < left.rows; ++y) {
      const int16_t* hyp = hypothesis.ptr<int16_t>(y);
      const float* l = left.ptr<float>(y);
      const float* r = right.ptr<float>(y);
      cv::Vec4f* g = gathered.ptr<cv::Vec4f>(y);
      for (int x = 0; x < left.cols; ++x) {
        const int d = hyp[x] + k, xr = x - d;
        const bool inside = hyp[x] >= 0 && d >= d_min && d <= d_max && xr >= 0;
        const float value = inside ? r[xr] : 0.0f;
        g[x] = cv::Vec4f(value, value * value, l[x] * value, inside ? 1.0f : 0.0f);
      }
    }
    cv::boxFilter(gathered, sums, -1, cv::Size(2 * h + 1, 2 * h + 1), cv::Point(-1, -1), false,
                  cv::BORDER_REPLICATE);
    for (int y = 0; y < left.rows; ++y)
      ScoreRow(sums.ptr<float>(y), ls.sum.ptr<float>(y), ls.variance.ptr<float>(y),
               hypothesis.ptr<int16_t>(y), k, n, left.cols, score->ptr<float>(y),
               disparity->ptr<int16_t>(y));
  }
}

// Twice the disparities of a coarser map at the finer size (bilinear where all four
// neighbours have one; otherwise the nearest).
cv::Mat Upsample(const cv::Mat& coarse, cv::Size size) {
  cv::Mat as_float, valid, up, up_valid;
  coarse.convertTo(as_float, CV_32F);
  valid = (coarse >= 0) / 255;
  valid.convertTo(valid, CV_32F);
  cv::resize(as_float.mul(valid), up, size, 0, 0, cv::INTER_LINEAR);
  cv::resize(valid, up_valid, size, 0, 0, cv::INTER_LINEAR);
  cv::Mat near;
  cv::resize(coarse, near, size, 0, 0, cv::INTER_NEAREST);
  cv::Mat out(size, CV_16SC1);
  for (int y = 0; y < size.height; ++y) {
    const float* u = up.ptr<float>(y);
    const float* w = up_valid.ptr<float>(y);
    const int16_t* nr = near.ptr<int16_t>(y);
    int16_t* o = out.ptr<int16_t>(y);
    for (int x = 0; x < size.width; ++x)
      o[x] = w[x] > 0.999f ? static_cast<int16_t>(std::lround(2.0f * u[x] / w[x]))
                           : static_cast<int16_t>(nr[x] >= 0 ? 2 * nr[x] : -1);
  }
  return out;
}

}  // namespace

DisparityMap MatchPyramid(const cv::Mat& left, const cv::Mat& right, int d_min, int d_max,
                          int finest_level, const PyramidNccOptions& o) {
  CV_Assert(left.type() == CV_32FC1 && right.type() == CV_32FC1 && left.size() == right.size());
  CV_Assert(d_min >= 0 && d_max > d_min && finest_level >= 0 && o.Check(nullptr));
  int top = finest_level;
  while (((d_max - d_min) >> top) > o.coarsest_search_px && (left.cols >> (top + 1)) > 32) ++top;
  std::vector<cv::Mat> lp, rp;
  cv::buildPyramid(left, lp, top);
  cv::buildPyramid(right, rp, top);
  DisparityMap map;
  map.level = top;
  SearchAll(lp[top], rp[top], d_min >> top, (d_max + (1 << top) - 1) >> top, o.half_window_px,
            &map.disparity, &map.score);
  for (int level = top - 1; level >= finest_level; --level) {
    const cv::Mat hypothesis = Upsample(map.disparity, lp[level].size());
    const int lo = d_min >> level, hi = (d_max + (1 << level) - 1) >> level;
    Refine(lp[level], rp[level], hypothesis, lo, hi, o.half_window_px, o.refine_radius_px,
           &map.disparity, &map.score);
    map.level = level;
  }
  return map;
}

namespace {

// sum of a[i] b[i], i < count (a multiple of four): four lanes at a time where there are SIMD
// registers (OpenCV's universal intrinsics).
float PaddedDot(const float* a, const float* b, int count) {
#if CV_SIMD128
  cv::v_float32x4 sum = cv::v_setzero_f32();
  for (int i = 0; i < count; i += 4) sum = cv::v_fma(cv::v_load(a + i), cv::v_load(b + i), sum);
  return cv::v_reduce_sum(sum);
#else
  float sum = 0.0f;
  for (int i = 0; i < count; ++i) sum += a[i] * b[i];
  return sum;
#endif
}

// sum of a[i], i < count (a multiple of four), likewise.
float PaddedSum(const float* a, int count) {
#if CV_SIMD128
  cv::v_float32x4 sum = cv::v_setzero_f32();
  for (int i = 0; i < count; i += 4) sum += cv::v_load(a + i);
  return cv::v_reduce_sum(sum);
#else
  float sum = 0.0f;
  for (int i = 0; i < count; ++i) sum += a[i];
  return sum;
#endif
}

}  // namespace

int BestDisparityAt(const cv::Mat& from, const cv::Mat& to, int u, int v, int lo, int hi, int h,
                    int sign, double* score) {
  if (v < h || v + h >= from.rows || u < h || u + h >= from.cols) return -1;
  // The candidates whose windows fit: columns c = u - sign d, from c_first to c_first + hi - lo.
  lo = std::max({lo, 0, sign > 0 ? u - to.cols + 1 + h : h - u});
  hi = std::min(hi, sign > 0 ? u - h : to.cols - 1 - h - u);
  if (score) *score = -2.0;
  if (lo > hi) return -1;
  const int w = 2 * h + 1, n = w * w;
  // The window of `from` less its mean, each row padded with zeros to whole chunks of four;
  // the sums below then run over whole chunks.
  const int stride = (w + 3) & ~3;
  cv::AutoBuffer<float, 256> window(static_cast<size_t>(w) * stride);  // on the stack for h <= 7
  std::fill(window.data(), window.data() + window.size(), 0.0f);
  for (int y = 0; y < w; ++y)
    std::copy_n(from.ptr<float>(v - h + y) + u - h, w, window.data() + y * stride);
  const float mean = PaddedSum(window.data(), w * stride) / n;
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x) window[y * stride + x] -= mean;
  const double vf = PaddedDot(window.data(), window.data(), w * stride);  // n times the variance
  // Column sums of the candidates' rows in `to` (less the same mean, against cancellation),
  // over every column a candidate window covers; a window's sums are then w columns'.
  const int c_first = std::min(u - sign * lo, u - sign * hi);
  const int first = c_first - h, columns = hi - lo + w;
  cv::AutoBuffer<float, 128> column_sum(columns), column_sq(columns);
  std::fill(column_sum.data(), column_sum.data() + columns, 0.0f);
  std::fill(column_sq.data(), column_sq.data() + columns, 0.0f);
  for (int y = -h; y <= h; ++y) {
    const float* t = to.ptr<float>(v + y) + first;
    for (int x = 0; x < columns; ++x) {
      const float value = t[x] - mean;
      column_sum[x] += value;
      column_sq[x] += value * value;
    }
  }
  int best_d = -1;
  double best = -2.0;
  for (int d = lo; d <= hi; ++d) {
    const int c = u - sign * d;
    // Whole padded rows where they stay inside the image (the padding meets zeros); else the
    // window's own width.
    const bool padded = c - h + stride <= to.cols;
    double sft = 0.0;
    for (int y = 0; y < w; ++y) {
      const float* t = to.ptr<float>(v - h + y) + c - h;
      const float* f = window.data() + y * stride;
      if (padded) {
        sft += PaddedDot(f, t, stride);
      } else {
        for (int x = 0; x < w; ++x) sft += f[x] * t[x];
      }
    }
    float st = 0.0f, stt = 0.0f;
    for (int x = c - h - first; x <= c + h - first; ++x) st += column_sum[x], stt += column_sq[x];
    const double var = vf * (stt - static_cast<double>(st) * st / n);
    if (!(var > 1e-6)) continue;
    const double ncc = sft / std::sqrt(var);  // the window of `from` has zero mean
    if (ncc > best) best = ncc, best_d = d;
  }
  if (score) *score = best;
  return best_d;
}

}  // namespace ts
