// Throughput of the geometry core that matching and intersection stand on: projections and
// two-ray intersections per second on one core. Informational until the matching targets
// of issue 5 use them.
#include <random>

#include "processing/geometry/intersection.h"
#include "processing/geometry/stereo_rig.h"
#include "tests/bench/bench_table.h"
#include "tests/common/paper_rig.h"

int main(int argc, char** argv) {
  using namespace ts;
  CameraIntrinsics c = testing::PaperCamera();
  c.k1 = -0.15;
  c.k2 = 0.08;
  c.p1 = 3e-4;
  const CameraModel camera(c);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> lateral(-10, 10), depth(3, 50);
  const int n = 200000;
  std::vector<Eigen::Vector3d> points(n);
  for (auto& p : points) p = {lateral(rng), 0.5 * lateral(rng), depth(rng)};

  bench::Table table("geometry core throughput");
  Eigen::Vector2d pixel;
  double sink = 0;
  const double project_s = bench::BestSeconds(3, [&] {
    for (const auto& p : points)
      if (camera.Project(p, &pixel)) sink += pixel.x();
  });
  table.Add({"project (distorted), per second", n / project_s, "1/s", ""});

  Eigen::Isometry3d left = Eigen::Isometry3d::Identity(), right = left;
  left.translation().x() = -0.25;
  right.translation().x() = 0.25;
  const int m = 50000;
  const double intersect_s = bench::BestSeconds(3, [&] {
    for (int i = 0; i < m; ++i) {
      RayObservation a{&camera, left, {}, 0.3}, b{&camera, right, {}, 0.3};
      if (!camera.Project(left.inverse() * points[i], &a.pixel) ||
          !camera.Project(right.inverse() * points[i], &b.pixel))
        continue;
      sink += IntersectRays({a, b}).point_world.z();
    }
  });
  table.Add({"two-ray intersection with covariance, per s", m / intersect_s, "1/s", ""});
  std::printf("(checksum %.3g)\n", sink);
  return table.Finish(argc, argv);
}
