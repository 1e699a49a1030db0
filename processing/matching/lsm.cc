#include "processing/matching/lsm.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <vector>

namespace ts {

bool LsmOptions::Check(std::string* why) const {
  std::string err;
  if (half_window_px < 2 || half_window_px > 50)
    err = "half_window_px must be in [2, 50]";
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

SearchGradients ComputeSearchGradients(const cv::Mat& search) {
  SearchGradients g;
  g.dx = cv::Mat::zeros(search.size(), CV_32FC1);
  g.dy = cv::Mat::zeros(search.size(), CV_32FC1);
  for (int y = 1; y + 1 < search.rows; ++y) {
    const float* up = search.ptr<float>(y - 1);
    const float* row = search.ptr<float>(y);
    const float* down = search.ptr<float>(y + 1);
    float* dx = g.dx.ptr<float>(y);
    float* dy = g.dy.ptr<float>(y);
    for (int x = 1; x + 1 < search.cols; ++x) {
      dx[x] = 0.5f * (row[x + 1] - row[x - 1]);
      dy[x] = 0.5f * (down[x] - up[x]);
    }
  }
  return g;
}

namespace {

// Bilinear sample; false outside the interior (one pixel margin for the gradients).
inline bool Sample(const cv::Mat& image, double x, double y, double* value) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 1 || y0 < 1 || x0 + 2 >= image.cols || y0 + 2 >= image.rows) return false;
  const double tx = x - x0, ty = y - y0;
  const float* r0 = image.ptr<float>(y0);
  const float* r1 = image.ptr<float>(y0 + 1);
  *value =
      (1 - ty) * ((1 - tx) * r0[x0] + tx * r0[x0 + 1]) + ty * ((1 - tx) * r1[x0] + tx * r1[x0 + 1]);
  return true;
}

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= a.size();
  mb /= b.size();
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

}  // namespace

LsmResult MatchLsm(const cv::Mat& templ, const Eigen::Vector2d& centre, const cv::Mat& search,
                   const SearchGradients& gradients, const Eigen::Vector2d& start,
                   const LsmOptions& o) {
  LsmResult result;
  if (!o.Check(&result.why)) return result;
  const int h = o.half_window_px;
  // The template window, sampled at integer offsets from its (possibly sub-pixel) centre.
  std::vector<double> f;
  f.reserve((2 * h + 1) * (2 * h + 1));
  for (int y = -h; y <= h; ++y)
    for (int x = -h; x <= h; ++x) {
      double v;
      if (!Sample(templ, centre.x() + x, centre.y() + y, &v)) {
        result.why = "template window leaves the image";
        return result;
      }
      f.push_back(v);
    }
  Eigen::Matrix<double, 8, 1> p;
  p << start.x(), 1, 0, start.y(), 0, 1, 0, 1;
  const int n = static_cast<int>(f.size());
  std::vector<double> g(n);
  Eigen::Matrix<double, 8, 8> normal;
  double sum_v2 = 0.0;
  for (result.iterations = 1; result.iterations <= o.max_iterations; ++result.iterations) {
    normal.setZero();
    Eigen::Matrix<double, 8, 1> rhs = Eigen::Matrix<double, 8, 1>::Zero();
    sum_v2 = 0.0;
    int k = 0;
    for (int y = -h; y <= h; ++y) {
      for (int x = -h; x <= h; ++x, ++k) {
        const double xs = p[0] + p[1] * x + p[2] * y, ys = p[3] + p[4] * x + p[5] * y;
        double gv, gx, gy;
        if (!Sample(search, xs, ys, &gv) || !Sample(gradients.dx, xs, ys, &gx) ||
            !Sample(gradients.dy, xs, ys, &gy)) {
          result.why = "search window leaves the image";
          return result;
        }
        g[k] = gv;
        const double v = f[k] - (p[6] + p[7] * gv);
        Eigen::Matrix<double, 8, 1> a;
        a << p[7] * gx, p[7] * gx * x, p[7] * gx * y, p[7] * gy, p[7] * gy * x, p[7] * gy * y, 1.0,
            gv;
        normal.selfadjointView<Eigen::Lower>().rankUpdate(a);
        rhs += a * v;
        sum_v2 += v * v;
      }
    }
    normal = normal.selfadjointView<Eigen::Lower>();
    const Eigen::LDLT<Eigen::Matrix<double, 8, 8>> ldlt(normal);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        std::abs(normal.determinant()) < 1e-300) {
      result.why = "no texture: normal equations singular";
      return result;
    }
    const Eigen::Matrix<double, 8, 1> step = ldlt.solve(rhs);
    if (!step.allFinite()) {
      result.why = "no texture: normal equations singular";
      return result;
    }
    p += step;
    if ((Eigen::Vector2d(p[0], p[3]) - start).norm() > o.max_shift_px) {
      result.why = "moved more than max_shift_px from the start";
      return result;
    }
    if (std::hypot(step[0], step[3]) < o.convergence_px) {
      const double sigma0_sq = sum_v2 / (n - 8);
      const Eigen::Matrix<double, 8, 8> covariance = sigma0_sq * normal.inverse();
      result.parameters = p;
      result.position_px = {p[0], p[3]};
      result.sigma0 = std::sqrt(sigma0_sq);
      result.sigma_x_px = std::sqrt(covariance(0, 0));
      result.sigma_y_px = std::sqrt(covariance(3, 3));
      result.correlation = Correlation(f, g);
      if (result.correlation < o.min_correlation) {
        result.why = "correlation below min_correlation";
      } else if (std::max(result.sigma_x_px, result.sigma_y_px) > o.max_sigma_px) {
        result.why = "sigma above max_sigma_px";
      } else {
        result.ok = true;
      }
      return result;
    }
  }
  result.why = "did not converge";
  return result;
}

}  // namespace ts
