#include "processing/calibration/calibration_validation.h"

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>

namespace ts {
namespace {

constexpr int kN = kIntrinsicCount;
using Map = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

std::vector<Eigen::Vector2d> Grid(const CameraIntrinsics& c, const ValidationOptions& o) {
  std::vector<Eigen::Vector2d> grid;
  for (int j = 0; j < o.grid_rows; ++j)
    for (int i = 0; i < o.grid_columns; ++i)
      grid.emplace_back(c.width_px * (i + 0.5) / o.grid_columns - 0.5,
                        c.height_px * (j + 0.5) / o.grid_rows - 0.5);
  return grid;
}

IntrinsicVector Intrinsics(const Eigen::VectorXd& p, int offset) {
  IntrinsicVector v;
  for (int j = 0; j < kN; ++j) v[j] = p[offset + j];
  return v;
}

Eigen::VectorXd StereoParameters(const StereoCalibration& s) {
  Eigen::VectorXd p(2 * kN + 6);
  const IntrinsicVector l = s.left.intrinsics.ToParameters(), r = s.right.intrinsics.ToParameters();
  const Pose6 pose = PoseFromIsometry(s.right_from_left);
  for (int j = 0; j < kN; ++j) p[j] = l[j], p[kN + j] = r[j];
  for (int j = 0; j < 6; ++j) p[2 * kN + j] = pose[j];
  return p;
}

// Where a point the left camera sees at each grid pixel, d away, appears in the right image;
// NaN where the right camera does not see it (its model is not validated beyond its frame).
Map StereoMap(const CameraIntrinsics& size, const std::vector<Eigen::Vector2d>& grid, double d) {
  return [=](const Eigen::VectorXd& p) {
    const CameraModel left(
        CameraIntrinsics::FromParameters(Intrinsics(p, 0), size.width_px, size.height_px, 0.0));
    const CameraModel right(
        CameraIntrinsics::FromParameters(Intrinsics(p, kN), size.width_px, size.height_px, 0.0));
    Pose6 pose;
    for (int j = 0; j < 6; ++j) pose[j] = p[2 * kN + j];
    const Eigen::Isometry3d right_from_left = IsometryFromPose(pose);
    Eigen::VectorXd out(2 * grid.size());
    for (size_t i = 0; i < grid.size(); ++i) {
      Eigen::Vector2d pixel;
      const bool seen = right.Project(right_from_left * (d * left.RayFromPixel(grid[i])), &pixel) &&
                        right.InImage(pixel);
      out.segment<2>(2 * i) = seen ? pixel : Eigen::Vector2d::Constant(std::nan(""));
    }
    return out;
  };
}

// The projection of fixed directions (the full calibration's rays through the grid).
Map CameraMap(const CameraIntrinsics& full, const std::vector<Eigen::Vector2d>& grid,
              const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  std::vector<Eigen::Vector3d> rays;
  const CameraModel model(full);
  for (const Eigen::Vector2d& u : grid) rays.push_back(rotation * model.RayFromPixel(u));
  return [=](const Eigen::VectorXd& p) {
    const CameraModel camera(
        CameraIntrinsics::FromParameters(Intrinsics(p, 0), full.width_px, full.height_px, 0.0));
    Eigen::VectorXd out(2 * rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      Eigen::Vector2d pixel = Eigen::Vector2d::Constant(std::nan(""));
      camera.Project(rays[i], &pixel);
      out.segment<2>(2 * i) = pixel;
    }
    return out;
  };
}

// d map / d parameters by central differences, each step a hundredth of the parameter's sigma
// (fixed parameters, sigma 0, do not move the map).
Eigen::MatrixXd Jacobian(const Map& map, const Eigen::VectorXd& p, const Eigen::MatrixXd& cov) {
  const Eigen::VectorXd at = map(p);
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(at.size(), p.size());
  for (int k = 0; k < p.size(); ++k) {
    const double h = 0.01 * std::sqrt(std::max(0.0, cov(k, k)));
    if (h <= 0.0) continue;
    Eigen::VectorXd plus = p, minus = p;
    plus[k] += h, minus[k] -= h;
    j.col(k) = (map(plus) - map(minus)) / (2.0 * h);
  }
  return j;
}

// The part of a change of the map a rotation of the camera cannot take up: I - R (R'R)^-1 R'
// with R the map's derivative by a small rotation about each axis.
Eigen::MatrixXd RotationFree(const CameraIntrinsics& full,
                             const std::vector<Eigen::Vector2d>& grid) {
  const Eigen::VectorXd p = Eigen::Map<const Eigen::VectorXd>(full.ToParameters().data(), kN);
  Eigen::MatrixXd r(2 * grid.size(), 3);
  constexpr double h = 1e-6;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Matrix3d plus = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(axis)).matrix();
    r.col(axis) =
        (CameraMap(full, grid, plus)(p) - CameraMap(full, grid, plus.transpose())(p)) / (2.0 * h);
  }
  return Eigen::MatrixXd::Identity(r.rows(), r.rows()) -
         r * (r.transpose() * r).inverse() * r.transpose();
}

double LargerAxis(const Eigen::Matrix2d& c) {
  return std::sqrt(
      std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c).eigenvalues()[1]));
}

void Summarise(MapValidation* m) {
  std::vector<double> sorted;
  for (double s : m->sigma_px)
    if (std::isfinite(s)) sorted.push_back(s);
  std::sort(sorted.begin(), sorted.end());
  m->max_sigma_px = sorted.empty() ? 0.0 : sorted.back();
  m->median_sigma_px = sorted.empty() ? 0.0 : sorted[sorted.size() / 2];
}

// The map's covariance over the grid (2N x 2N), through `free` when the rotation is taken up.
Eigen::MatrixXd MapCovariance(const Map& map, const Eigen::VectorXd& p, const Eigen::MatrixXd& cov,
                              const Eigen::MatrixXd* free) {
  const Eigen::MatrixXd j = Jacobian(map, p, cov);
  const Eigen::MatrixXd c = j * cov * j.transpose();
  return free ? Eigen::MatrixXd(*free * c * free->transpose()) : c;
}

MapValidation Predicted(const Eigen::MatrixXd& covariance, double distance_m) {
  MapValidation m;
  m.distance_m = distance_m;
  for (int i = 0; i < covariance.rows() / 2; ++i)
    m.sigma_px.push_back(covariance.block<2, 2>(2 * i, 2 * i).allFinite()
                             ? LargerAxis(covariance.block<2, 2>(2 * i, 2 * i))
                             : std::nan(""));
  Summarise(&m);
  return m;
}

// The halves' difference against the sigma they predict for it.
void Compare(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::MatrixXd& cov_a,
             const Eigen::MatrixXd& cov_b, const Eigen::MatrixXd* free, MapValidation* m) {
  Eigen::VectorXd d = a - b;
  if (free) d = *free * d;
  double sum = 0.0;
  int n = 0;
  for (int i = 0; i < d.size() / 2; ++i) {
    const Eigen::Vector2d di = d.segment<2>(2 * i);
    const Eigen::Matrix2d ci = cov_a.block<2, 2>(2 * i, 2 * i) + cov_b.block<2, 2>(2 * i, 2 * i);
    m->difference_px.push_back(di.norm());
    if (!di.allFinite() || !ci.allFinite() || ci.determinant() <= 0.0) continue;
    sum += di.dot(ci.inverse() * di) / 2.0;
    ++n;
  }
  m->split = n > 0;
  for (double di : m->difference_px)
    if (std::isfinite(di)) m->max_difference_px = std::max(m->max_difference_px, di);
  m->consistency = n > 0 ? std::sqrt(sum / n) : 0.0;
}

// Alternate placements of the views (their stereo partners with them).
TargetViews Half(const TargetViews& views, const std::set<int>& placements, int half) {
  TargetViews out = views;
  out.views.clear();
  for (const TargetView& v : views.views) {
    const int rank =
        static_cast<int>(std::distance(placements.begin(), placements.find(v.placement)));
    if (rank % 2 == half) out.views.push_back(v);
  }
  return out;
}

std::set<int> Placements(const std::vector<const TargetViews*>& cameras) {
  std::set<int> placements;
  for (const TargetViews* c : cameras)
    for (const TargetView& v : c->views) placements.insert(v.placement);
  return placements;
}

void Judge(const FrameCoverage& coverage, const CameraCalibrationOptions& options,
           const ValidationOptions& o, CalibrationValidation* out) {
  const CalibrationValidation& v = *out;
  const MapValidation* worst = &v.maps[0];
  const MapValidation* least_consistent = &v.maps[0];
  for (const MapValidation& m : v.maps) {
    if (m.max_sigma_px > worst->max_sigma_px) worst = &m;
    if (m.consistency > least_consistent->consistency) least_consistent = &m;
  }
  const auto where = [](const MapValidation& m) {
    return m.distance_m > 0.0 ? " at " + fmt::format("{:.0f}", m.distance_m) + " m" : std::string();
  };
  if (least_consistent->split && least_consistent->consistency > o.max_consistency) {
    out->verdict = "overfitted";
    out->reason = "the two halves of the views differ by up to " +
                  fmt::format("{:.2f}", least_consistent->max_difference_px) + " px" +
                  where(*least_consistent) + ", " +
                  fmt::format("{:.1f}", least_consistent->consistency) +
                  " times what their sigmas allow: the model follows the noise or an error it "
                  "does not know (a board that is not flat, blurred or misidentified views)";
  } else if (worst->max_sigma_px > o.good_uncertainty_px) {
    const bool edges = coverage.border_share < options.warn_border_coverage;
    out->verdict = edges ? "needs views at the edges" : "needs more views";
    out->reason = "the map is uncertain to " + fmt::format("{:.2f}", worst->max_sigma_px) + " px" +
                  where(*worst) + " (" + fmt::format("{:.2f}", worst->median_sigma_px) +
                  " px at the median), more than " + fmt::format("{:.2f}", o.good_uncertainty_px) +
                  " px" +
                  (edges ? "; only " + fmt::format("{:.0f}", 100.0 * coverage.border_share) +
                               " % of the cells along the frame's edges hold observations"
                         : std::string());
  } else {
    out->verdict = "good";
    out->reason = "the map is known within " + fmt::format("{:.3f}", worst->max_sigma_px) + " px " +
                  (worst->distance_m > 0.0 ? "wherever both cameras see" : "over the frame") +
                  where(*worst);
    if (least_consistent->split)
      out->reason += "; the two halves of the views agree within " +
                     fmt::format("{:.1f}", least_consistent->consistency) + " of their sigmas";
  }
  if (!v.split_note.empty()) out->reason += " (" + v.split_note + ")";
}

}  // namespace

CalibrationValidation ValidateStereo(const StereoCalibration& full, const TargetViews& left,
                                     const TargetViews& right,
                                     const CameraCalibrationOptions& options,
                                     const ValidationOptions& o) {
  CalibrationValidation v;
  v.columns = o.grid_columns, v.rows = o.grid_rows;
  v.grid = Grid(full.left.intrinsics, o);
  const std::set<int> placements = Placements({&left, &right});
  Result<StereoCalibration> halves[2] = {Error{""}, Error{""}};
  for (int h = 0; h < 2; ++h)
    halves[h] = CalibrateStereo(Half(left, placements, h), Half(right, placements, h), options,
                                &full.left.intrinsics, &full.right.intrinsics);
  for (int h = 0; h < 2; ++h)
    if (!halves[h]) v.split_note = "a half of the views alone: " + halves[h].error();
  const Eigen::VectorXd p = StereoParameters(full);
  for (double d : {o.near_m, o.far_m}) {
    const Map map = StereoMap(full.left.intrinsics, v.grid, d);
    MapValidation m = Predicted(MapCovariance(map, p, full.joint_covariance, nullptr), d);
    if (v.split_note.empty()) {
      const Eigen::VectorXd pa = StereoParameters(*halves[0]), pb = StereoParameters(*halves[1]);
      Compare(map(pa), map(pb), MapCovariance(map, pa, halves[0]->joint_covariance, nullptr),
              MapCovariance(map, pb, halves[1]->joint_covariance, nullptr), nullptr, &m);
    }
    v.maps.push_back(std::move(m));
  }
  FrameCoverage coverage = full.left.coverage;
  if (full.right.coverage.border_share < coverage.border_share) coverage = full.right.coverage;
  Judge(coverage, options, o, &v);
  return v;
}

CalibrationValidation ValidateCamera(const CameraCalibration& full, const TargetViews& views,
                                     const CameraCalibrationOptions& options,
                                     const ValidationOptions& o) {
  CalibrationValidation v;
  v.columns = o.grid_columns, v.rows = o.grid_rows;
  v.grid = Grid(full.intrinsics, o);
  const Map map = CameraMap(full.intrinsics, v.grid);
  const Eigen::MatrixXd free = RotationFree(full.intrinsics, v.grid);
  const auto parameters = [](const CameraCalibration& c) {
    const IntrinsicVector p = c.intrinsics.ToParameters();
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(p.data(), kN));
  };
  MapValidation m = Predicted(MapCovariance(map, parameters(full), full.covariance, &free), 0.0);
  const std::set<int> placements = Placements({&views});
  Result<CameraCalibration> halves[2] = {Error{""}, Error{""}};
  for (int h = 0; h < 2; ++h)
    halves[h] = CalibrateCamera(Half(views, placements, h), options, &full.intrinsics);
  for (int h = 0; h < 2; ++h)
    if (!halves[h]) v.split_note = "a half of the views alone: " + halves[h].error();
  if (v.split_note.empty()) {
    const Eigen::VectorXd pa = parameters(*halves[0]), pb = parameters(*halves[1]);
    Compare(map(pa), map(pb), MapCovariance(map, pa, halves[0]->covariance, &free),
            MapCovariance(map, pb, halves[1]->covariance, &free), &free, &m);
  }
  v.maps.push_back(std::move(m));
  Judge(full.coverage, options, o, &v);
  return v;
}

}  // namespace ts
