#include "processing/cloud/underside_patches.h"

#include <Eigen/Cholesky>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "processing/cloud/grid_index.h"

namespace ts {

bool UndersidePatchOptions::Check(std::string* why) const {
  return CheckDeclaredOptions(*this, why);
}

UndersidePatches FindUndersidePatches(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<uint8_t>& ground,
                                      const Eigen::Vector3d& viewpoint,
                                      const UndersidePatchOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("UndersidePatchOptions: " + why);
  if (ground.size() != points.size())
    throw std::invalid_argument("FindUndersidePatches: one ground flag per point is needed");
  UndersidePatches result;
  result.underside.assign(points.size(), 0);
  std::vector<Eigen::Vector3d> ground_points;
  std::vector<int> ground_index;
  for (size_t i = 0; i < points.size(); ++i)
    if (ground[i] && points[i].allFinite())
      ground_points.push_back(points[i]), ground_index.push_back(static_cast<int>(i));
  const GridIndex grid(ground_points, o.cell_m);
  if (grid.cols() == 0) return result;

  // Patches: the ground cells, joined where at most gap_cells empty cells apart (dilated by
  // half the gap, they touch).
  cv::Mat occupied(grid.rows(), grid.cols(), CV_8UC1, cv::Scalar(0));
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c)
      if (grid.Count(c, r) > 0) occupied.at<uint8_t>(r, c) = 255;
  const int half_gap = (o.gap_cells + 1) / 2;
  cv::Mat joined, labels;
  cv::dilate(
      occupied, joined,
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * half_gap + 1, 2 * half_gap + 1)));
  const int count = cv::connectedComponents(joined, labels, 8, CV_32S);
  std::vector<std::vector<cv::Point>> cells(count);
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c)
      if (occupied.at<uint8_t>(r, c)) cells[labels.at<int>(r, c)].emplace_back(c, r);

  // Object points (the others) per cell of the same grid, for the patches among objects.
  cv::Mat objects(grid.rows(), grid.cols(), CV_32SC1, cv::Scalar(0));
  for (size_t i = 0; i < points.size(); ++i) {
    if (ground[i] || !points[i].allFinite()) continue;
    const int c = grid.ColOf(points[i].x()), r = grid.RowOf(points[i].y());
    if (grid.Inside(c, r)) ++objects.at<int>(r, c);
  }
  // Object points in a patch's cells and object_ring_cells around them (within the patch's
  // bounding box grown by the ring, not the whole grid).
  auto objects_around = [&](const std::vector<cv::Point>& patch) {
    const int ring = o.object_ring_cells;
    const cv::Rect box = cv::Rect(cv::boundingRect(patch).tl() - cv::Point(ring, ring),
                                  cv::boundingRect(patch).br() + cv::Point(ring, ring)) &
                         cv::Rect(0, 0, grid.cols(), grid.rows());
    cv::Mat mask(box.size(), CV_8UC1, cv::Scalar(0));
    for (const cv::Point& p : patch) mask.at<uint8_t>(p - box.tl()) = 255;
    const int k = 2 * ring + 1;
    cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
    long n = 0;
    for (int r = 0; r < box.height; ++r)
      for (int c = 0; c < box.width; ++c)
        if (mask.at<uint8_t>(r, c)) n += objects.at<int>(r + box.y, c + box.x);
    return n;
  };

  const double cell_area = o.cell_m * o.cell_m;
  for (int label = 1; label < count; ++label) {  // 0: the background
    if (cells[label].size() * cell_area >= o.max_area_m2) continue;
    ++result.small_patches;
    std::vector<int> members;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const cv::Point& p : cells[label])
      for (const int* i = grid.begin(p.x, p.y); i != grid.end(p.x, p.y); ++i)
        members.push_back(*i), mean += ground_points[*i];
    if (static_cast<int>(members.size()) < o.min_points) continue;
    if (o.object_ratio > 0.0 &&
        objects_around(cells[label]) >= o.object_ratio * static_cast<double>(members.size())) {
      ++result.among_objects;
      for (const int i : members) result.underside[ground_index[i]] = 1;
      continue;
    }
    mean /= static_cast<double>(members.size());
    // z = a + b x + c y about the patch's mean point.
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const int i : members) {
      const Eigen::Vector3d q = ground_points[i] - mean;
      const Eigen::Vector3d a(1.0, q.x(), q.y());
      normal += a * a.transpose();
      rhs += a * q.z();
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(normal);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        !(ldlt.vectorD().minCoeff() > 1e-9 * ldlt.vectorD().maxCoeff()))
      continue;  // points on a line: no plane
    const Eigen::Vector3d plane = ldlt.solve(rhs);
    const Eigen::Vector3d sight = mean - viewpoint;
    const double run = sight.head<2>().norm();
    if (!(run > 0.0)) continue;
    const Eigen::Vector2d away = sight.head<2>() / run;
    const double terrain_slope = plane[1] * away.x() + plane[2] * away.y();
    const double sight_slope = sight.z() / run;
    if (terrain_slope >= sight_slope - o.slope_margin) continue;
    ++result.underside_patches;
    for (const int i : members) result.underside[ground_index[i]] = 1;
  }
  return result;
}

}  // namespace ts
