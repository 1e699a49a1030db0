#include "processing/matching/rectification.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

namespace ts {

namespace {

// Projection of the rectified pixel (u, v) into the camera; false where it does not exist.
bool Source(const CameraModel& camera, const Eigen::Matrix3d& camera_from_rect,
            const Rectification& r, double u, double v, Eigen::Vector2d* pixel) {
  const Eigen::Vector3d ray(u - r.principal_point_px.x(), v - r.principal_point_px.y(), r.focal_px);
  return camera.Project(camera_from_rect * ray, pixel);
}

// The maps are exact at every kStep-th pixel and bilinear between: the lens distortion is
// smooth, so the interpolation is far below a thousandth of a pixel (tested), at 1/64 of the
// cost of projecting (Newton on the distortion) every pixel. Blocks with a corner that does
// not project are computed pixel by pixel.
void BuildMaps(const CameraModel& camera, const Eigen::Matrix3d& camera_from_rect,
               const Rectification& r, cv::Mat* map_x, cv::Mat* map_y) {
  constexpr int kStep = 8;
  const int nodes_x = (r.width_px - 1 + kStep - 1) / kStep + 1;
  const int nodes_y = (r.height_px - 1 + kStep - 1) / kStep + 1;
  cv::Mat node_x(nodes_y, nodes_x, CV_64FC1), node_y(nodes_y, nodes_x, CV_64FC1);
  cv::Mat valid(nodes_y, nodes_x, CV_8UC1);
  for (int j = 0; j < nodes_y; ++j)
    for (int i = 0; i < nodes_x; ++i) {
      Eigen::Vector2d pixel;
      valid.at<uint8_t>(j, i) = Source(camera, camera_from_rect, r, i * kStep, j * kStep, &pixel);
      node_x.at<double>(j, i) = pixel.x();
      node_y.at<double>(j, i) = pixel.y();
    }
  map_x->create(r.height_px, r.width_px, CV_32FC1);
  map_y->create(r.height_px, r.width_px, CV_32FC1);
  cv::parallel_for_(cv::Range(0, r.height_px), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      float* mx = map_x->ptr<float>(v);
      float* my = map_y->ptr<float>(v);
      const int j = v / kStep;
      const double ty = static_cast<double>(v - j * kStep) / kStep;
      for (int u = 0; u < r.width_px; ++u) {
        const int i = u / kStep;
        const double tx = static_cast<double>(u - i * kStep) / kStep;
        const bool corners = valid.at<uint8_t>(j, i) && valid.at<uint8_t>(j, i + 1) &&
                             valid.at<uint8_t>(j + 1, i) && valid.at<uint8_t>(j + 1, i + 1);
        Eigen::Vector2d pixel;
        if (corners) {
          auto lerp = [&](const cv::Mat& n) {
            const double top =
                n.at<double>(j, i) + tx * (n.at<double>(j, i + 1) - n.at<double>(j, i));
            const double bottom =
                n.at<double>(j + 1, i) + tx * (n.at<double>(j + 1, i + 1) - n.at<double>(j + 1, i));
            return top + ty * (bottom - top);
          };
          pixel = {lerp(node_x), lerp(node_y)};
        } else if (!Source(camera, camera_from_rect, r, u, v, &pixel)) {
          pixel = {-1.0, -1.0};  // outside: remap's border value
        }
        mx[u] = static_cast<float>(pixel.x());
        my[u] = static_cast<float>(pixel.y());
      }
    }
  });
}

}  // namespace

Eigen::Vector2d Rectification::LeftPixel(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = left_from_rect.transpose() * p;
  return principal_point_px + focal_px * Eigen::Vector2d(q.x() / q.z(), q.y() / q.z());
}

Eigen::Vector2d Rectification::RightPixel(const Eigen::Vector3d& p_left) const {
  // The right centre sits at +B along the rectified x axis.
  const Eigen::Vector3d q =
      left_from_rect.transpose() * p_left - Eigen::Vector3d(baseline_m, 0.0, 0.0);
  return principal_point_px + focal_px * Eigen::Vector2d(q.x() / q.z(), q.y() / q.z());
}

Rectification Rectify(const StereoRig& rig) {
  // The rig frame S already has X along the baseline: a rectified camera is S's nominal
  // camera (looking along Y_S, rows along X_S), for both sides.
  Rectification r;
  r.left_from_rect = rig.S_from_left.transpose() * StereoRig::NominalSFromCamera();
  r.right_from_rect = rig.left_from_right.transpose() * r.left_from_rect;
  r.baseline_m = rig.baseline_m;
  r.width_px = rig.left.width_px;
  r.height_px = rig.left.height_px;
  r.focal_px = std::min(rig.left.principal_distance_px, rig.right.principal_distance_px);
  r.principal_point_px = {0.5 * (r.width_px - 1), 0.5 * (r.height_px - 1)};
  BuildMaps(CameraModel(rig.left), r.left_from_rect, r, &r.left_map_x, &r.left_map_y);
  BuildMaps(CameraModel(rig.right), r.right_from_rect, r, &r.right_map_x, &r.right_map_y);
  return r;
}

int Rectification::MinDisparityPx(double max_depth_m) const {
  return std::max(0, static_cast<int>(std::floor(focal_px * baseline_m / max_depth_m)));
}

int Rectification::MaxDisparityPx(double min_depth_m) const {
  return static_cast<int>(std::ceil(focal_px * baseline_m / min_depth_m));
}

void RectifyPair(const Rectification& r, const cv::Mat& left, const cv::Mat& right,
                 cv::Mat* left_rect, cv::Mat* right_rect) {
  cv::Mat l, rr;
  left.convertTo(l, CV_32F);
  right.convertTo(rr, CV_32F);
  cv::remap(l, *left_rect, r.left_map_x, r.left_map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  cv::remap(rr, *right_rect, r.right_map_x, r.right_map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            0);
}

}  // namespace ts
