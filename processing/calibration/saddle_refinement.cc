#include "processing/calibration/saddle_refinement.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace ts {
namespace {

// A window's gradients must fix the corner in both directions: the weaker of the two
// principal directions at least this share of the stronger (one straight edge alone fixes
// nothing along it).
constexpr double kMinGradientIsotropy = 1e-2;

struct Gradients {
  cv::Mat gx, gy;  // CV_32F
};

Gradients SmoothedGradients(const cv::Mat& grey, double smoothing_px) {
  cv::Mat image;
  grey.convertTo(image, CV_32F);
  if (smoothing_px > 0.0) cv::GaussianBlur(image, image, cv::Size(), smoothing_px);
  Gradients g;
  cv::Sobel(image, g.gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(image, g.gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  return g;
}

// Bilinear sample; false outside the image.
bool Sample(const cv::Mat& m, double x, double y, double* value) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= m.cols || y0 + 1 >= m.rows) return false;
  const double fx = x - x0, fy = y - y0;
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y0 + 1);
  *value =
      (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

// One step: the point where the window's gradients about `q` are orthogonal to the lines
// from it. The samples lie at q + integer offsets, symmetric about q, so that for a junction
// symmetric about its centre each sample's contribution is matched by its mirror's.
bool Step(const Gradients& g, size_t corner, const Eigen::Vector2d& q, double half,
          const SaddlePixelTest& usable, Eigen::Vector2d* next) {
  const int reach = static_cast<int>(std::floor(half));
  const double window_sigma = 0.5 * half;
  Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      const Eigen::Vector2d p = q + Eigen::Vector2d(dx, dy);
      if (usable && !usable(corner, p)) continue;
      double gx, gy;
      if (!Sample(g.gx, p.x(), p.y(), &gx) || !Sample(g.gy, p.x(), p.y(), &gy)) return false;
      const double w = std::exp(-(dx * dx + dy * dy) / (2.0 * window_sigma * window_sigma));
      const Eigen::Vector2d grad(gx, gy);
      const Eigen::Matrix2d ggt = w * grad * grad.transpose();
      a += ggt;
      b += ggt * p;
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(a);
  if (!(eigen.eigenvalues()(1) > 0.0) ||
      eigen.eigenvalues()(0) < kMinGradientIsotropy * eigen.eigenvalues()(1))
    return false;
  *next = a.ldlt().solve(b);
  return next->allFinite();
}

}  // namespace

void RefineSaddles(const cv::Mat& grey, const std::vector<double>& half_window,
                   const SaddlePixelTest& usable, const SaddleRefinementOptions& options,
                   std::vector<Eigen::Vector2d>* corners, std::vector<bool>* refined) {
  const Gradients g = SmoothedGradients(grey, options.smoothing_px);
  refined->assign(corners->size(), false);
  for (size_t k = 0; k < corners->size(); ++k) {
    const Eigen::Vector2d start = (*corners)[k];
    const double half = half_window[k];
    if (!(half >= 1.0)) continue;
    Eigen::Vector2d q = start;
    bool converged = false;
    for (int it = 0; it < options.max_iterations; ++it) {
      Eigen::Vector2d next;
      if (!Step(g, k, q, half, usable, &next) || (next - start).norm() > half) break;
      const double step = (next - q).norm();
      q = next;
      if (step < options.tolerance_px) {
        converged = true;
        break;
      }
    }
    if (!converged) continue;
    (*corners)[k] = q;
    (*refined)[k] = true;
  }
}

}  // namespace ts
