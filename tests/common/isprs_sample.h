#pragma once
// The ISPRS filter-test samples of ../shared/data/ground_filter/isprs: every point of a
// sample with its reference label (ground when it is also in sampNN-utm-ground.pcd), and the
// error rates of Sithole & Vosselman (2004) for a classification.
#include <Eigen/Core>
#include <cstdint>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "processing/io/point_cloud_file.h"

namespace ts::testing {

inline const std::vector<std::string> kIsprsSamples = {"samp11", "samp21", "samp31",
                                                       "samp51", "samp61", "samp71"};

struct IsprsSample {
  std::vector<Eigen::Vector3d> points;
  std::vector<uint8_t> reference_ground;
};

inline std::string IsprsPath(const std::string& sample, bool ground_only = false) {
  return std::string(TS_SHARED_DATA_DIR) + "/ground_filter/isprs/" + sample +
         (ground_only ? "-utm-ground.pcd" : "-utm.pcd");
}

inline IsprsSample LoadIsprsSample(const std::string& sample) {
  IsprsSample s;
  s.points = ReadPointCloudXyz(IsprsPath(sample)).value();
  const std::vector<Eigen::Vector3d> ground = ReadPointCloudXyz(IsprsPath(sample, true)).value();
  std::set<std::tuple<double, double, double>> keys;
  for (const Eigen::Vector3d& p : ground) keys.emplace(p.x(), p.y(), p.z());
  s.reference_ground.resize(s.points.size());
  for (size_t i = 0; i < s.points.size(); ++i)
    s.reference_ground[i] = keys.count({s.points[i].x(), s.points[i].y(), s.points[i].z()});
  return s;
}

struct FilterErrors {
  double type1 = 0.0;  // reference ground rejected / reference ground
  double type2 = 0.0;  // objects accepted as ground / reference objects
  double total = 0.0;  // misclassified / all points
};

inline FilterErrors ClassificationErrors(const std::vector<uint8_t>& reference,
                                         const std::vector<uint8_t>& ground) {
  double n_ground = 0, n_object = 0, rejected = 0, accepted = 0;
  for (size_t i = 0; i < reference.size(); ++i) {
    if (reference[i]) {
      ++n_ground;
      rejected += !ground[i];
    } else {
      ++n_object;
      accepted += ground[i] != 0;
    }
  }
  return {rejected / n_ground, accepted / n_object, (rejected + accepted) / reference.size()};
}

}  // namespace ts::testing
