#include "processing/cloud/sight_line_objects.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/core.hpp>
#include <stdexcept>

namespace ts {

bool SightLineOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!(face_max_below_deg > face_min_below_deg))
    err = "need face_min_below_deg < face_max_below_deg";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

namespace {

constexpr double kRadPerDeg = M_PI / 180.0;
constexpr size_t kMaxFaceRays = 15;

struct Ray {
  double elevation;  // rad
  double distance;   // horizontal, m
  double height;     // above the viewpoint, m
  double sigma;      // of the horizontal distance, m
  size_t index;
  bool operator<(const Ray& other) const { return elevation < other.elevation; }
};

// Rays grouped by (pair, azimuth bin), each group sorted by elevation: one sort of them all.
std::vector<std::vector<Ray>> Bins(const PointCloud& cloud,
                                   const std::map<int, Eigen::Vector3d>& viewpoints,
                                   double bin_deg) {
  const double bin = bin_deg * kRadPerDeg;
  std::vector<std::pair<int64_t, Ray>> keyed;
  keyed.reserve(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const auto viewpoint = viewpoints.find(cloud[i].pair);
    if (viewpoint == viewpoints.end()) continue;
    const Eigen::Vector3d d = cloud[i].position_m - viewpoint->second;
    const double distance = d.head<2>().norm();
    if (!(distance > 0.0)) continue;
    // Sigma of the horizontal distance: the covariance along the line of sight.
    const Eigen::Vector2d along = d.head<2>() / distance;
    const double variance =
        along.dot(cloud[i].covariance_m2.topLeftCorner<2, 2>().cast<double>() * along);
    const auto az = static_cast<int64_t>(std::floor((std::atan2(d.y(), d.x()) + M_PI) / bin));
    keyed.push_back(
        {(static_cast<int64_t>(cloud[i].pair) << 32) | az,
         {std::atan2(d.z(), distance), distance, d.z(), std::sqrt(std::max(0.0, variance)), i}});
  }
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;
  });
  std::vector<std::vector<Ray>> out;
  for (size_t k = 0; k < keyed.size(); ++k) {
    if (k == 0 || keyed[k].first != keyed[k - 1].first) out.emplace_back();
    out.back().push_back(keyed[k].second);
  }
  return out;
}

void FindFloating(const std::vector<std::vector<Ray>>& bins, const SightLineOptions& o,
                  SightLineObjects* result) {
  std::vector<double> farthest;  // witnesses so far, largest first
  for (const std::vector<Ray>& rays : bins) {
    farthest.assign(o.min_witnesses, -INFINITY);
    for (const Ray& r : rays) {
      if (farthest.back() > r.distance + std::max(o.min_gap_m, o.sigma_factor * r.sigma)) {
        result->floating[r.index] = 1;
        ++result->floating_count;
      }
      // This ray as a witness for the ones above: its distance less its own uncertainty.
      const double witness = r.distance - o.sigma_factor * r.sigma;
      if (witness > farthest.back()) {
        farthest.back() = witness;
        std::sort(farthest.begin(), farthest.end(), std::greater<double>());
      }
    }
  }
}

void FindFaces(const std::vector<std::vector<Ray>>& bins, const SightLineOptions& o,
               SightLineObjects* result) {
  const double steepest = std::tan(o.max_terrain_inclination_deg * kRadPerDeg);
  const double min_below = o.face_min_below_deg * kRadPerDeg;
  const double max_below = o.face_max_below_deg * kRadPerDeg;
  const auto middle = [](std::vector<double>* v) {
    std::nth_element(v->begin(), v->begin() + v->size() / 2, v->end());
    return (*v)[v->size() / 2];
  };
  std::vector<double> rise, run;
  for (const std::vector<Ray>& rays : bins) {
    size_t first = 0, end = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
      const Ray& p = rays[k];
      while (first < k && rays[first].elevation < p.elevation - max_below) ++first;
      end = std::max(end, first);
      while (end < k && rays[end].elevation <= p.elevation - min_below) ++end;
      // At most kMaxFaceRays of them, evenly spread (near the tripod a bin holds hundreds).
      rise.clear();
      run.clear();
      const size_t stride = std::max<size_t>(1, (end - first) / kMaxFaceRays);
      for (size_t j = first; j < end; j += stride) {
        rise.push_back(p.height - rays[j].height);
        run.push_back(p.distance - rays[j].distance);
      }
      if (static_cast<int>(rise.size()) < o.min_face_rays) continue;
      const double dz = middle(&rise), dd = middle(&run);
      if (dz > 0.0 && dd * steepest < dz) {
        result->on_face[p.index] = 1;
        ++result->face_count;
      }
    }
  }
}

}  // namespace

SightLineObjects FindSightLineObjects(const PointCloud& cloud,
                                      const std::map<int, Eigen::Vector3d>& viewpoints,
                                      const SightLineOptions& o) {
  std::string why;
  if (!o.Check(&why)) throw std::invalid_argument("sight-line objects: " + why);
  SightLineObjects result;
  result.floating.assign(cloud.size(), 0);
  result.on_face.assign(cloud.size(), 0);
  // The two tests are independent: one core each.
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int test = range.start; test < range.end; ++test) {
      if (test == 0) FindFloating(Bins(cloud, viewpoints, o.azimuth_bin_deg), o, &result);
      if (test == 1) FindFaces(Bins(cloud, viewpoints, o.face_bin_deg), o, &result);
    }
  });
  return result;
}

}  // namespace ts
