#include "sim/rasterizer.h"

#include <algorithm>
#include <cmath>

namespace ts::sim {
namespace {
constexpr double kNearM = 0.05;  // near plane; the visible ground is metres away
}  // namespace

void ViewRasterizer::Rasterize(const SceneMesh& mesh, const CameraModel& camera,
                               const Eigen::Isometry3d& camera_from_L, int samples_per_px) {
  const CameraIntrinsics& in = camera.intrinsics();
  focal_ = in.principal_distance_px;
  pp_x_ = in.principal_point_x_px;
  pp_y_ = in.principal_point_y_px;
  samples_ = samples_per_px;
  // Ideal-plane bounds of the frame: undistort its border.
  min_x_ = min_y_ = 1e300;
  max_x_ = max_y_ = -1e300;
  auto extend = [&](double x, double y) {
    const Eigen::Vector2d ideal = camera.Undistort({x, y});
    min_x_ = std::min(min_x_, ideal.x());
    max_x_ = std::max(max_x_, ideal.x());
    min_y_ = std::min(min_y_, ideal.y());
    max_y_ = std::max(max_y_, ideal.y());
  };
  const double w = in.width_px - 0.5, h = in.height_px - 0.5;
  for (double x = -0.5; x < w; x += 4) extend(x, -0.5), extend(x, h);
  for (double y = -0.5; y < h; y += 4) extend(-0.5, y), extend(w, y);
  extend(w, h);
  min_x_ -= 1.0, min_y_ -= 1.0, max_x_ += 1.0, max_y_ += 1.0;
  width_ = static_cast<int>(std::ceil((max_x_ - min_x_) * samples_));
  height_ = static_cast<int>(std::ceil((max_y_ - min_y_) * samples_));
  inverse_depth_.assign(static_cast<size_t>(width_) * height_, 0.0f);
  ids_.assign(static_cast<size_t>(width_) * height_, -1);

  camera_points_.resize(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    camera_points_[i] = camera_from_L * mesh.vertices[i];

  // Frustum half-planes in camera coordinates: x f > (max_x - pp) z etc.
  const double right = (max_x_ - pp_x_) / focal_, left = (min_x_ - pp_x_) / focal_;
  const double bottom = (max_y_ - pp_y_) / focal_, top = (min_y_ - pp_y_) / focal_;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Eigen::Vector3d& a = camera_points_[tri[0]];
    const Eigen::Vector3d& b = camera_points_[tri[1]];
    const Eigen::Vector3d& c = camera_points_[tri[2]];
    if (a.z() < kNearM && b.z() < kNearM && c.z() < kNearM) continue;
    auto outside = [&](auto test) { return test(a) && test(b) && test(c); };
    if (outside([&](const Eigen::Vector3d& p) { return p.x() > right * p.z(); }) ||
        outside([&](const Eigen::Vector3d& p) { return p.x() < left * p.z(); }) ||
        outside([&](const Eigen::Vector3d& p) { return p.y() > bottom * p.z(); }) ||
        outside([&](const Eigen::Vector3d& p) { return p.y() < top * p.z(); }))
      continue;
    ClipAndDraw(a, b, c, static_cast<int32_t>(t));
  }
}

void ViewRasterizer::ClipAndDraw(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c, int32_t id) {
  if (a.z() >= kNearM && b.z() >= kNearM && c.z() >= kNearM) return DrawTriangle(a, b, c, id);
  // Sutherland-Hodgman against z >= near: a triangle becomes 0, 3 or 4 vertices.
  Eigen::Vector3d in[3] = {a, b, c}, out[4];
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& p = in[i];
    const Eigen::Vector3d& q = in[(i + 1) % 3];
    const bool p_in = p.z() >= kNearM, q_in = q.z() >= kNearM;
    if (p_in) out[n++] = p;
    if (p_in != q_in) out[n++] = p + (q - p) * ((kNearM - p.z()) / (q.z() - p.z()));
  }
  for (int i = 1; i + 1 < n; ++i) DrawTriangle(out[0], out[i], out[i + 1], id);
}

void ViewRasterizer::DrawTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c, int32_t id) {
  // Buffer coordinates: sample (i, j) has its centre at (i + 0.5, j + 0.5).
  auto project = [&](const Eigen::Vector3d& p, double* x, double* y) {
    *x = (pp_x_ + focal_ * p.x() / p.z() - min_x_) * samples_;
    *y = (pp_y_ + focal_ * p.y() / p.z() - min_y_) * samples_;
  };
  double x0, y0, x1, y1, x2, y2;
  project(a, &x0, &y0);
  project(b, &x1, &y1);
  project(c, &x2, &y2);
  const double area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
  if (std::abs(area) < 1e-12) return;
  const int bx0 = std::max(0, static_cast<int>(std::floor(std::min({x0, x1, x2}) - 0.5)));
  const int bx1 = std::min(width_ - 1, static_cast<int>(std::ceil(std::max({x0, x1, x2}))));
  const int by0 = std::max(0, static_cast<int>(std::floor(std::min({y0, y1, y2}) - 0.5)));
  const int by1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max({y0, y1, y2}))));
  if (bx0 > bx1 || by0 > by1) return;
  const double inv_area = 1.0 / area;
  const double iz0 = 1.0 / a.z(), iz1 = 1.0 / b.z(), iz2 = 1.0 / c.z();
  // Barycentric weights are affine in (x, y): w = w(bx0+0.5, y) + dw/dx * i.
  const double dw0_dx = (y1 - y2) * inv_area, dw1_dx = (y2 - y0) * inv_area;
  for (int by = by0; by <= by1; ++by) {
    const double sx = bx0 + 0.5, sy = by + 0.5;
    double w0 = ((x1 - sx) * (y2 - sy) - (x2 - sx) * (y1 - sy)) * inv_area;
    double w1 = ((x2 - sx) * (y0 - sy) - (x0 - sx) * (y2 - sy)) * inv_area;
    float* depth = &inverse_depth_[static_cast<size_t>(by) * width_];
    int32_t* ids = &ids_[static_cast<size_t>(by) * width_];
    for (int bx = bx0; bx <= bx1; ++bx, w0 += dw0_dx, w1 += dw1_dx) {
      const double w2 = 1.0 - w0 - w1;
      if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
      const float iz = static_cast<float>(w0 * iz0 + w1 * iz1 + w2 * iz2);
      if (iz > depth[bx]) {
        depth[bx] = iz;
        ids[bx] = id;
      }
    }
  }
}

}  // namespace ts::sim
