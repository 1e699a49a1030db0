#include "processing/matching/triangulation.h"

namespace ts {

bool TriangulateRectified(const Rectification& r, const StereoMatch& m, Eigen::Vector3d* point,
                          Eigen::Matrix3d* covariance) {
  const double d = m.disparity_px;
  if (!(d > 0.0)) return false;
  const double b = r.baseline_m;
  const double x = m.left_px.x() - r.principal_point_px.x();
  const double y = m.left_px.y() - r.principal_point_px.y();
  *point = Eigen::Vector3d(x, y, r.focal_px) * (b / d);
  const Eigen::Vector3d j = -*point / d;  // d point / d disparity
  *covariance = j * j.transpose() * (m.sigma_disparity_px * m.sigma_disparity_px);
  return true;
}

void AppendPairPoints(const Rectification& r, const std::vector<StereoMatch>& matches,
                      const Eigen::Isometry3d& l_from_left_camera, int pair, PointCloud* cloud) {
  const Eigen::Matrix3d rotation = l_from_left_camera.linear() * r.left_from_rect;
  cloud->reserve(cloud->size() + matches.size());
  for (const StereoMatch& m : matches) {
    Eigen::Vector3d p;
    Eigen::Matrix3d c;
    if (!TriangulateRectified(r, m, &p, &c)) continue;
    CloudPoint q;
    q.position_m = l_from_left_camera.translation() + rotation * p;
    q.covariance_m2 = (rotation * c * rotation.transpose()).cast<float>();
    q.pair = pair;
    q.correlation = static_cast<float>(m.correlation);
    q.sigma_disparity_px = static_cast<float>(m.sigma_disparity_px);
    q.window = {m.left_px.cast<float>(), m.half_window_px.cast<float>()};
    cloud->push_back(q);
  }
}

}  // namespace ts
