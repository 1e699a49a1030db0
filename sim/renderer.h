#pragma once
// Renders what one camera of the rig sees of a scene, with the project's camera model.
//
// Every ray comes from the camera model (explicit back-projection, distortion included), the
// visible triangle from the rasteriser, and the 3D point from intersecting the ray with that
// triangle's plane (for the terrain, re-located on the lattice until the point lies in the
// triangle whose plane it is on: the rendered surface is exactly Scene::TerrainHeight).
//
// Anti-aliasing, two kinds:
//  - Edges (a silhouette, the skyline, an object against the ground): supersampling x
//    supersampling samples per pixel wherever the samples see different surfaces.
//  - Texture: band-limited to the pixel's footprint on the surface (texture.h). At grazing
//    angles that footprint is long in range and narrow across; the pixel is shaded with up
//    to kMaxProbes probes spread along its range axis, each filtered at the narrow width
//    (anisotropic filtering), so the across-range detail that stereo matching needs survives
//    without aliasing along range.
// Shading: albedo times sky light plus Lambertian sunlight; no cast shadows yet. The result
// is noise-free radiance; sensor.h turns it into an image.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "core/options.h"

#include "processing/geometry/camera_model.h"
#include "sim/rasterizer.h"
#include "sim/scene.h"
#include "sim/scene_mesh.h"
#include "sim/texture.h"

namespace ts::sim {

struct RenderOptions {
  int supersampling = 2;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("supersampling", self.supersampling, {"samples per pixel along each axis", "", 1, 8});
  }
  bool Check(std::string* why) const;
};

struct RenderStats {
  double rasterize_s = 0.0;  // visibility buffer
  double shade_s = 0.0;      // rays, intersections, texture, lighting
};

class Renderer {
 public:
  // Borrows scene and mesh; they must outlive the renderer. Not thread-safe (one per thread).
  Renderer(const Scene& scene, const SceneMesh& mesh) : scene_(scene), mesh_(mesh) {}

  // Radiance per pixel (CV_32FC1; 1 = white surface facing the sun). If range_m is given it
  // receives the distance from the projection centre to the surface at each pixel centre
  // (CV_32FC1, NaN for sky).
  cv::Mat Render(const CameraModel& camera, const Eigen::Isometry3d& L_from_camera,
                 const RenderOptions& options, cv::Mat* range_m = nullptr);
  const RenderStats& last_stats() const { return stats_; }

 private:
  struct Hit {
    int32_t triangle = -1;
    double t = 0.0;  // along the unnormalised ray direction
  };
  struct View;
  Hit Intersect(const Eigen::Vector3d& centre, const Eigen::Vector3d& direction,
                int32_t triangle) const;
  // Radiance along the ray through an ideal pixel position, texture filtered to footprint_m
  // (or, if footprint_m <= 0, to the isotropic footprint of `pixel_fraction` of a pixel).
  // material: the ground material to use (the pixel's), or null to evaluate it here.
  double ShadeRay(const View& view, const Eigen::Vector2d& ideal, double footprint_m,
                  double pixel_fraction, const GroundMaterial* material = nullptr) const;
  double ShadePixel(const View& view, const Eigen::Vector2d& pixel) const;

  const Scene& scene_;
  const SceneMesh& mesh_;
  ViewRasterizer rasterizer_;
  RenderStats stats_;
};

}  // namespace ts::sim
