#pragma once
// Visibility for one view: which mesh triangle is nearest along each sample's ray.
//
// Triangles are rasterised in the *ideal* (distortion-free) image plane, where perspective
// keeps their edges straight; the renderer then maps each distorted pixel sample to the ideal
// plane with the camera model's explicit correction and looks the triangle up here. The exact
// 3D point comes from the ray itself (see renderer.h), so this buffer only has to be right
// about which surface is visible. Not thread-safe: one rasteriser per thread.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "processing/geometry/camera_model.h"
#include "sim/scene_mesh.h"

namespace ts::sim {

class ViewRasterizer {
 public:
  // samples_per_px: buffer resolution per ideal pixel along each axis.
  void Rasterize(const SceneMesh& mesh, const CameraModel& camera,
                 const Eigen::Isometry3d& camera_from_L, int samples_per_px);
  // Triangle index visible at an ideal pixel position, -1 for none (sky).
  int32_t TriangleAt(double ideal_x_px, double ideal_y_px) const {
    const int bx = static_cast<int>(std::floor((ideal_x_px - min_x_) * samples_));
    const int by = static_cast<int>(std::floor((ideal_y_px - min_y_) * samples_));
    if (bx < 0 || by < 0 || bx >= width_ || by >= height_) return -1;
    return ids_[static_cast<size_t>(by) * width_ + bx];
  }

 private:
  void DrawTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    int32_t id);
  void ClipAndDraw(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   int32_t id);

  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;  // ideal-plane bounds, px
  int samples_ = 1, width_ = 0, height_ = 0;
  double focal_ = 1, pp_x_ = 0, pp_y_ = 0;
  std::vector<float> inverse_depth_;
  std::vector<int32_t> ids_;
  std::vector<Eigen::Vector3d> camera_points_;
};

}  // namespace ts::sim
