#include "sim/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/texture.h"

namespace ts::sim {
namespace {
constexpr double kSkyRadiance = 1.3;  // brighter than any lit ground: clips like a real sky
constexpr int kMaxRelocations = 6;
}  // namespace

bool RenderOptions::Check(std::string* why) const { return CheckDeclaredOptions(*this, why); }

Renderer::Hit Renderer::Intersect(const Eigen::Vector3d& centre, const Eigen::Vector3d& d,
                                  int32_t triangle) const {
  Hit hit;
  for (int i = 0; i <= kMaxRelocations; ++i) {
    const Eigen::Vector3d& n = mesh_.normals[triangle];
    const double denominator = n.dot(d);
    if (std::abs(denominator) < 1e-12) return hit;
    const double t = (mesh_.plane_offsets[triangle] - n.dot(centre)) / denominator;
    if (!(t > 0.0)) return hit;
    hit = {triangle, t};
    if (triangle >= mesh_.terrain_triangles) return hit;  // objects: the rasteriser decides
    const Eigen::Vector3d p = centre + t * d;
    int ix, iy, half;
    if (!scene_.LocateTriangle(p.x(), p.y(), &ix, &iy, &half)) return hit;
    const int32_t located = SceneMesh::TerrainTriangle(scene_, ix, iy, half);
    if (located == triangle) return hit;
    triangle = located;
  }
  return hit;
}

struct Renderer::View {
  const CameraModel* camera;
  Eigen::Matrix3d rotation;  // L_from_camera
  Eigen::Vector3d centre;    // projection centre in L
  Eigen::Vector2d pp;
  double focal_px;
  int supersampling;
  Eigen::Vector3d Direction(const Eigen::Vector2d& ideal) const {
    return rotation * Eigen::Vector3d(ideal.x() - pp.x(), ideal.y() - pp.y(), focal_px);
  }
};

namespace {
constexpr int kMaxProbes = 6;
// Surfaces a pixel's samples may share: sky, terrain, or one object.
int SurfaceKey(const SceneMesh& mesh, int32_t triangle) {
  if (triangle < 0) return -1;
  return triangle < mesh.terrain_triangles ? -2 : mesh.objects[triangle];
}
}  // namespace

double Renderer::ShadeRay(const View& view, const Eigen::Vector2d& ideal, double footprint_m,
                          double pixel_fraction, const GroundMaterial* material) const {
  const int32_t triangle = rasterizer_.TriangleAt(ideal.x(), ideal.y());
  if (triangle < 0) return kSkyRadiance;
  const Eigen::Vector3d d = view.Direction(ideal);
  const Hit hit = Intersect(view.centre, d, triangle);
  if (hit.triangle < 0) return kSkyRadiance;
  const Eigen::Vector3d p = view.centre + hit.t * d;
  const Eigen::Vector3d& n = mesh_.normals[hit.triangle];
  if (footprint_m <= 0.0) {
    const double incidence = std::max(std::abs(n.dot(d)) / d.norm(), 0.05);
    footprint_m = hit.t * d.norm() / view.focal_px * pixel_fraction / incidence;
  }
  const Surface surface = mesh_.surfaces[hit.triangle];
  double albedo;
  if (surface == Surface::kTerrain) {
    albedo = GroundAlbedo(
        scene_.seed,
        material ? *material : GroundMaterialAt(scene_.seed, p.x(), p.y(), footprint_m), p.x(),
        p.y(), footprint_m);
  } else {
    albedo = ObjectAlbedo(scene_.seed + mesh_.objects[hit.triangle], surface, p, footprint_m);
  }
  const Lighting& light = scene_.lighting;
  return albedo * (light.ambient + light.direct * std::max(0.0, n.dot(light.to_sun)));
}

double Renderer::ShadePixel(const View& view, const Eigen::Vector2d& pixel) const {
  Eigen::Matrix2d j;  // d ideal / d pixel: maps sub-pixel offsets to the ideal plane
  const Eigen::Vector2d ideal = view.camera->Undistort(pixel, &j);
  const int ss = view.supersampling;
  Eigen::Vector2d samples[64];
  int key = 0;
  bool uniform = true;
  for (int sy = 0; sy < ss; ++sy) {
    for (int sx = 0; sx < ss; ++sx) {
      const Eigen::Vector2d offset((sx + 0.5) / ss - 0.5, (sy + 0.5) / ss - 0.5);
      const Eigen::Vector2d& s = samples[sy * ss + sx] = ideal + j * offset;
      const int k = SurfaceKey(mesh_, rasterizer_.TriangleAt(s.x(), s.y()));
      if (sy == 0 && sx == 0) key = k;
      uniform = uniform && k == key;
    }
  }
  if (uniform && key == -1) return kSkyRadiance;
  if (!uniform) {  // an edge: plain supersampling
    double sum = 0.0;
    for (int i = 0; i < ss * ss; ++i) sum += ShadeRay(view, samples[i], 0.0, 1.0 / ss);
    return sum / (ss * ss);
  }
  // One surface: anisotropic texture filtering along the pixel's range axis.
  const int32_t triangle = rasterizer_.TriangleAt(ideal.x(), ideal.y());
  const Eigen::Vector3d d = view.Direction(ideal);
  const Hit centre = triangle < 0 ? Hit{} : Intersect(view.centre, d, triangle);
  if (centre.triangle < 0) return ShadeRay(view, ideal, 0.0, 1.0);
  const double across = centre.t * d.norm() / view.focal_px;
  const double incidence =
      std::max(std::abs(mesh_.normals[centre.triangle].dot(d)) / d.norm(), 0.05);
  const double ratio = 1.0 / incidence;  // footprint length / width
  const int probes = std::clamp(static_cast<int>(std::ceil(ratio / 2.0)), 1, kMaxProbes);
  const double footprint = std::max(across, across * ratio / probes);
  const Eigen::Vector3d p = view.centre + centre.t * d;
  const GroundMaterial material = GroundMaterialAt(scene_.seed, p.x(), p.y(), footprint);
  double sum = 0.0;
  for (int k = 0; k < probes; ++k) {
    const Eigen::Vector2d offset(0.0, (k + 0.5) / probes - 0.5);
    sum += ShadeRay(view, ideal + j * offset, footprint, 1.0, &material);
  }
  return sum / probes;
}

cv::Mat Renderer::Render(const CameraModel& camera, const Eigen::Isometry3d& L_from_camera,
                         const RenderOptions& options, cv::Mat* range_m) {
  const CameraIntrinsics& in = camera.intrinsics();
  const auto t0 = std::chrono::steady_clock::now();
  rasterizer_.Rasterize(mesh_, camera, L_from_camera.inverse(), options.supersampling);
  const auto t1 = std::chrono::steady_clock::now();
  const View view{&camera,
                  L_from_camera.linear(),
                  L_from_camera.translation(),
                  {in.principal_point_x_px, in.principal_point_y_px},
                  in.principal_distance_px,
                  options.supersampling};
  cv::Mat radiance(in.height_px, in.width_px, CV_32FC1);
  if (range_m) range_m->create(in.height_px, in.width_px, CV_32FC1);
  for (int y = 0; y < in.height_px; ++y) {
    float* row = radiance.ptr<float>(y);
    for (int x = 0; x < in.width_px; ++x) {
      row[x] = static_cast<float>(ShadePixel(view, Eigen::Vector2d(x, y)));
      if (range_m) {
        const Eigen::Vector2d ideal = camera.Undistort(Eigen::Vector2d(x, y));
        const Eigen::Vector3d d = view.Direction(ideal);
        const int32_t triangle = rasterizer_.TriangleAt(ideal.x(), ideal.y());
        const Hit hit = triangle < 0 ? Hit{} : Intersect(view.centre, d, triangle);
        range_m->at<float>(y, x) =
            hit.triangle < 0 ? std::nanf("") : static_cast<float>(hit.t * d.norm());
      }
    }
  }
  stats_.rasterize_s = std::chrono::duration<double>(t1 - t0).count();
  stats_.shade_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  return radiance;
}

}  // namespace ts::sim
