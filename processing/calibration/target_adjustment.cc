#include "processing/calibration/target_adjustment.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/calib3d.hpp>

#include "processing/calibration/measured_residual.h"
#include "processing/common/family_wise.h"

namespace ts {
namespace {

constexpr int kN = kIntrinsicCount;
// Re-weighings of the survey against the images, at most (they settle in two or three).
constexpr int kMaxWeightRounds = 8;

template <typename T>
void Transform(const T* pose, const T* in, T* out) {
  ceres::AngleAxisRotatePoint(pose, in, out);
  out[0] += pose[3], out[1] += pose[4], out[2] += pose[5];
}

// The first camera sees the target point through the placement's pose.
struct FirstCameraResidual {
  Eigen::Vector2d pixel;
  template <typename T>
  bool operator()(const T* intrinsics, const T* pose, const T* point, T* residual) const {
    T p[3];
    Transform(pose, point, p);
    return MeasuredResidual(intrinsics, p, pixel, residual);
  }
};

// The second camera through the placement's pose and the relative orientation.
struct SecondCameraResidual {
  Eigen::Vector2d pixel;
  template <typename T>
  bool operator()(const T* intrinsics, const T* relative, const T* pose, const T* point,
                  T* residual) const {
    T first[3], p[3];
    Transform(pose, point, first);
    Transform(relative, first, p);
    return MeasuredResidual(intrinsics, p, pixel, residual);
  }
};

// A surveyed target point as an observation of its own: its sigma in the target's unit, the
// residual scaled to image pixels so that it weighs against the image observations.
struct SurveyedPointResidual {
  Eigen::Vector3d surveyed;
  double weight;  // image sigma / survey sigma
  template <typename T>
  bool operator()(const T* point, T* residual) const {
    for (int j = 0; j < 3; ++j) residual[j] = weight * (point[j] - surveyed[j]);
    return true;
  }
};

// The principal distance of Zhang's closed form (OpenCV's initCameraMatrix2D, principal point
// at the frame's centre) over the given views; 0 when they do not determine one.
double ZhangFocalLength(const std::vector<std::vector<cv::Point3f>>& object,
                        const std::vector<std::vector<cv::Point2f>>& image, cv::Size size) {
  const cv::Mat k = cv::initCameraMatrix2D(object, image, size, 1.0);
  const double f = k.at<double>(1, 1);
  return f > 0.0 && std::isfinite(f) ? f : 0.0;
}

// Zhang's closed form over one camera's views of a planar target. Its least squares over all
// views can fail (a negative f^2) when a few views with small, distant boards outweigh the
// rest; then the median of the views that determine f alone.
Status ZhangStart(const TargetViews& views, IntrinsicVector* intrinsics) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const TargetView& v : views.views) {
    if (v.pixels.size() < 4) continue;
    object.emplace_back();
    image.emplace_back();
    for (size_t i = 0; i < v.ids.size(); ++i) {
      const Eigen::Vector3d& t = views.target[v.ids[i]];
      object.back().emplace_back(t.x(), t.y(), t.z());
      image.back().emplace_back(v.pixels[i].x(), v.pixels[i].y());
    }
  }
  if (object.size() < 3) return Error{"at least 3 views of the target are needed"};
  const cv::Size size(views.width_px, views.height_px);
  double f = ZhangFocalLength(object, image, size);
  if (f == 0.0) {
    std::vector<double> single;
    for (size_t v = 0; v < object.size(); ++v)
      if (const double fv = ZhangFocalLength({object[v]}, {image[v]}, size); fv > 0.0)
        single.push_back(fv);
    if (single.size() < 3)
      return Error{"the views do not determine a focal length (are they all parallel?)"};
    std::nth_element(single.begin(), single.begin() + single.size() / 2, single.end());
    f = single[single.size() / 2];
  }
  intrinsics->fill(0.0);
  (*intrinsics)[0] = f;
  (*intrinsics)[1] = 0.5 * (size.width - 1);
  (*intrinsics)[2] = 0.5 * (size.height - 1);
  return {};
}

// Each view's pose by resection with the starting camera (distortion undone first). A view
// whose points give no pose (degenerate: on one line or one pixel) is left out and named.
Status ResectViews(TargetViews* views, const IntrinsicVector& intrinsics,
                   std::map<int, Eigen::Isometry3d>* poses, std::vector<std::string>* left_out) {
  const CameraIntrinsics camera =
      CameraIntrinsics::FromParameters(intrinsics, views->width_px, views->height_px, 0.0);
  std::vector<TargetView> kept;
  for (TargetView& v : views->views) {
    if (v.pixels.size() < 6) return Error{"view " + v.name + ": fewer than 6 target points"};
    std::vector<Eigen::Vector3d> target;
    for (int id : v.ids) target.push_back(views->target[id]);
    const std::optional<Eigen::Isometry3d> pose = Resect(target, v.pixels, camera);
    if (!pose) {
      left_out->push_back(v.name);
      continue;
    }
    (*poses)[v.placement] = *pose;
    kept.push_back(std::move(v));
  }
  views->views = std::move(kept);
  return {};
}

// The relative orientation as the median (by baseline length) of the placements both saw.
Status StartRelativeOrientation(const std::map<int, Eigen::Isometry3d>& first,
                                const std::map<int, Eigen::Isometry3d>& second,
                                Eigen::Isometry3d* second_from_first) {
  std::vector<std::pair<double, Eigen::Isometry3d>> candidates;
  for (const auto& [placement, pose] : second)
    if (auto it = first.find(placement); it != first.end()) {
      const Eigen::Isometry3d relative = pose * it->second.inverse();
      candidates.emplace_back(relative.translation().norm(), relative);
    }
  if (candidates.empty())
    return Error{"no placement of the target is seen by both cameras: pair the views"};
  std::nth_element(candidates.begin(), candidates.begin() + candidates.size() / 2, candidates.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  *second_from_first = candidates[candidates.size() / 2].second;
  return {};
}

void EnsureRejectionFlags(TargetAdjustment* a) {
  a->rejected.resize(a->cameras.size());
  for (size_t c = 0; c < a->cameras.size(); ++c) {
    a->rejected[c].resize(a->cameras[c].views.size());
    for (size_t v = 0; v < a->cameras[c].views.size(); ++v)
      a->rejected[c][v].resize(a->cameras[c].views[v].pixels.size(), 0);
  }
}

// Target points whose survey leaves them free to move, observed (and not rejected) in some
// view.
std::vector<char> AdjustedPoints(const TargetAdjustment& a) {
  const TargetViews& first = a.cameras[0];
  std::vector<char> adjusted(a.target.size(), 0);
  if (a.image_sigma_px <= 0.0) return adjusted;
  for (size_t c = 0; c < a.cameras.size(); ++c)
    for (size_t v = 0; v < a.cameras[c].views.size(); ++v) {
      const TargetView& view = a.cameras[c].views[v];
      for (size_t i = 0; i < view.ids.size(); ++i) {
        const int id = view.ids[i];
        const bool rejected = c < a.rejected.size() && v < a.rejected[c].size() &&
                              i < a.rejected[c][v].size() && a.rejected[c][v][i];
        if (!rejected && static_cast<size_t>(id) < first.target_sigma.size() &&
            first.target_sigma[id] > 0.0)
          adjusted[id] = 1;
      }
    }
  return adjusted;
}

void AddSurveyedPoints(TargetAdjustment* a, ceres::Problem* problem) {
  const std::vector<char> adjusted = AdjustedPoints(*a);
  const TargetViews& first = a->cameras[0];
  for (size_t id = 0; id < a->target.size(); ++id) {
    if (!problem->HasParameterBlock(a->target[id].data())) continue;
    if (!adjusted[id]) {
      problem->SetParameterBlockConstant(a->target[id].data());
      continue;
    }
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<SurveyedPointResidual, 3, 3>(new SurveyedPointResidual{
            first.target[id], a->image_sigma_px / first.target_sigma[id]}),
        nullptr, a->target[id].data());
  }
}

void AddResiduals(TargetAdjustment* a, const TargetAdjustmentOptions& o, ceres::Problem* problem) {
  for (size_t c = 0; c < a->cameras.size(); ++c) {
    const TargetViews& camera = a->cameras[c];
    for (size_t v = 0; v < camera.views.size(); ++v) {
      const TargetView& view = camera.views[v];
      double* pose = a->first_from_target.at(view.placement).data();
      for (size_t i = 0; i < view.pixels.size(); ++i) {
        if (a->rejected[c][v][i]) continue;
        double* point = a->target[view.ids[i]].data();
        std::unique_ptr<ceres::CostFunction> cost;
        std::vector<double*> blocks;
        if (c == 0) {
          cost = std::make_unique<ceres::AutoDiffCostFunction<FirstCameraResidual, 2, kN, 6, 3>>(
              new FirstCameraResidual{view.pixels[i]});
          blocks = {a->intrinsics[c].data(), pose, point};
        } else {
          cost =
              std::make_unique<ceres::AutoDiffCostFunction<SecondCameraResidual, 2, kN, 6, 6, 3>>(
                  new SecondCameraResidual{view.pixels[i]});
          blocks = {a->intrinsics[c].data(), a->second_from_first.data(), pose, point};
        }
        // A point the current model cannot project would stop Ceres before its first step: a
        // gross error for this round, judged again after it.
        double residual[2];
        if (!cost->Evaluate(blocks.data(), residual, nullptr)) {
          a->rejected[c][v][i] = 1;
          continue;
        }
        ceres::LossFunction* loss = o.huber_px > 0.0 ? new ceres::HuberLoss(o.huber_px) : nullptr;
        problem->AddResidualBlock(cost.release(), loss, blocks);
      }
    }
  }
  AddSurveyedPoints(a, problem);
  for (size_t c = 0; c < a->cameras.size(); ++c) {
    std::vector<int> fixed;
    for (int j = 0; j < kN; ++j)
      if (a->fixed[c][j]) fixed.push_back(j);
    if (!fixed.empty())
      problem->SetManifold(a->intrinsics[c].data(), new ceres::SubsetManifold(kN, fixed));
  }
}

Status Solve(ceres::Problem* problem, const TargetAdjustmentOptions& o, int* iterations) {
  // Ceres reports through glog; what matters reaches the caller as a Result.
  FLAGS_minloglevel = google::GLOG_FATAL;
  ceres::Solver::Options solver;
  solver.logging_type = ceres::SILENT;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_num_iterations = o.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-12;
  solver.num_threads = 2;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, problem, &summary);
  *iterations += static_cast<int>(summary.iterations.size());
  // A model driven to where it cannot project its own points does not describe the views.
  if (!summary.IsSolutionUsable())
    return Error{"the adjustment does not fit the views (" + summary.message +
                 "): is the board size right?"};
  return {};
}

// sigma0 from the inliers (image_squares: the images' part of its sum). Then, when it may, every
// observation is judged again against k sigma0 (one rejected earlier comes back when it fits);
// returns how many judgements changed.
int JudgeOutliers(TargetAdjustment* a, const TargetAdjustmentOptions& o, bool may_reject,
                  AdjustmentPrecision* precision, double* image_squares) {
  const auto residuals = TargetResiduals(*a);
  double sum = 0.0;
  int inliers = 0, all = 0;
  for (size_t c = 0; c < residuals.size(); ++c)
    for (size_t v = 0; v < residuals[c].size(); ++v)
      for (size_t i = 0; i < residuals[c][v].size(); ++i, ++all)
        if (!a->rejected[c][v][i]) sum += residuals[c][v][i].squaredNorm(), ++inliers;
  *image_squares = sum;
  const std::vector<char> adjusted = AdjustedPoints(*a);
  const TargetViews& first = a->cameras[0];
  for (size_t id = 0; id < adjusted.size(); ++id)
    if (adjusted[id])
      sum += (a->image_sigma_px / first.target_sigma[id] * (a->target[id] - first.target[id]))
                 .squaredNorm();
  precision->observations = all;
  // Each adjusted point brings three unknowns and its three surveyed coordinates.
  precision->redundancy = 2 * inliers - a->FreeParameters() +
                          3 * static_cast<int>(std::count(adjusted.begin(), adjusted.end(), 1));
  precision->sigma0_px = std::sqrt(sum / std::max(1, precision->redundancy));
  precision->rejected = all - inliers;
  // Over all residual coordinates at once, so that a clean set of any size keeps all its points.
  precision->rejection_k =
      o.rejection_k > 0.0 ? o.rejection_k : FamilyWiseCriticalValue(2 * all, o.rejection_alpha);
  if (!may_reject || precision->redundancy <= 0) return 0;
  const double limit = precision->rejection_k * precision->sigma0_px;
  int changed = 0;
  for (size_t c = 0; c < residuals.size(); ++c)
    for (size_t v = 0; v < residuals[c].size(); ++v)
      for (size_t i = 0; i < residuals[c][v].size(); ++i) {
        const char outlier = residuals[c][v][i].cwiseAbs().maxCoeff() > limit;
        changed += a->rejected[c][v][i] != outlier;
        a->rejected[c][v][i] = outlier;
      }
  return changed;
}

// False when the normal matrix is singular: some free parameter is not determined.
bool EstimateCovariance(TargetAdjustment* a, ceres::Problem* problem,
                        AdjustmentPrecision* precision) {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  ceres::Covariance covariance(options);
  std::vector<std::pair<double*, int>> parameters;
  for (auto& intrinsics : a->intrinsics) parameters.emplace_back(intrinsics.data(), kN);
  if (a->cameras.size() == 2) parameters.emplace_back(a->second_from_first.data(), 6);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (size_t i = 0; i < parameters.size(); ++i)
    for (size_t j = i; j < parameters.size(); ++j)
      blocks.emplace_back(parameters[i].first, parameters[j].first);
  if (!covariance.Compute(blocks, problem)) return false;
  const double scale = precision->sigma0_px * precision->sigma0_px;
  int size = 0;
  for (const auto& p : parameters) size += p.second;
  precision->covariance = Eigen::MatrixXd::Zero(size, size);
  for (size_t i = 0, row = 0; i < parameters.size(); row += parameters[i++].second)
    for (size_t j = i, column = row; j < parameters.size(); column += parameters[j++].second) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(
          parameters[i].second, parameters[j].second);
      if (!covariance.GetCovarianceBlock(parameters[i].first, parameters[j].first, c.data()))
        return false;
      precision->covariance.block(row, column, c.rows(), c.cols()) = scale * c;
      precision->covariance.block(column, row, c.cols(), c.rows()) = scale * c.transpose();
    }
  return true;
}

// The sigma of an image coordinate as the images' variance component (Foerstner 1979): their
// squared residuals over their share of the redundancy, which is the whole redundancy less the
// surveyed points' share, sum over points of w^2 trace(Q_point) (w: a point's weight, Q: its
// cofactor block). 0 when no point is surveyed, or the share is not known.
double ImageSigmaComponent(TargetAdjustment* a, ceres::Problem* problem,
                           const AdjustmentPrecision& precision, double image_squares) {
  std::vector<char> adjusted = AdjustedPoints(*a);
  std::vector<std::pair<const double*, const double*>> blocks;
  for (size_t id = 0; id < adjusted.size(); ++id)
    if (adjusted[id] && problem->HasParameterBlock(a->target[id].data()))
      blocks.emplace_back(a->target[id].data(), a->target[id].data());
    else
      adjusted[id] = 0;
  if (blocks.empty()) return 0.0;
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  ceres::Covariance covariance(options);
  if (!covariance.Compute(blocks, problem)) return 0.0;
  const TargetViews& first = a->cameras[0];
  double survey_share = 0.0;
  for (size_t id = 0; id < adjusted.size(); ++id) {
    if (!adjusted[id]) continue;
    Eigen::Matrix3d q;
    if (!covariance.GetCovarianceBlock(a->target[id].data(), a->target[id].data(), q.data()))
      return 0.0;
    const double w = a->image_sigma_px / first.target_sigma[id];
    survey_share += w * w * q.trace();
  }
  const double image_share = precision.redundancy - survey_share;
  return image_share > 0.0 ? std::sqrt(image_squares / image_share) : 0.0;
}

}  // namespace

Pose6 PoseFromIsometry(const Eigen::Isometry3d& t) {
  Pose6 pose;
  const Eigen::Matrix3d rotation = t.linear();
  ceres::RotationMatrixToAngleAxis(rotation.data(), pose.data());
  for (int j = 0; j < 3; ++j) pose[3 + j] = t.translation()[j];
  return pose;
}

std::optional<Eigen::Isometry3d> Resect(const std::vector<Eigen::Vector3d>& target,
                                        const std::vector<Eigen::Vector2d>& pixels,
                                        const CameraIntrinsics& camera) {
  const CameraModel model(camera);
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> ideal;
  for (size_t i = 0; i < target.size(); ++i) {
    const Eigen::Vector2d u = model.Undistort(pixels[i]);
    object.emplace_back(target[i].x(), target[i].y(), target[i].z());
    ideal.emplace_back(u.x(), u.y());
  }
  const cv::Mat k =
      (cv::Mat_<double>(3, 3) << camera.principal_distance_px, 0, camera.principal_point_x_px, 0,
       camera.principal_distance_px, camera.principal_point_y_px, 0, 0, 1);
  cv::Mat rvec, tvec;
  if (object.size() < 4) return std::nullopt;
  try {
    if (!cv::solvePnP(object, ideal, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_SQPNP) ||
        !cv::solvePnP(object, ideal, k, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE))
      return std::nullopt;
  } catch (const cv::Exception&) {
    // SQPnP asserts on degenerate points (all on one pixel, non-finite): no pose, not a crash.
    return std::nullopt;
  }
  Pose6 pose;
  for (int j = 0; j < 3; ++j) pose[j] = rvec.at<double>(j), pose[3 + j] = tvec.at<double>(j);
  return IsometryFromPose(pose);
}

Eigen::Isometry3d IsometryFromPose(const Pose6& pose) {
  Eigen::Matrix3d rotation;  // column-major, as Ceres writes it
  ceres::AngleAxisToRotationMatrix(pose.data(), rotation.data());
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = rotation;
  t.translation() = Eigen::Vector3d(pose[3], pose[4], pose[5]);
  return t;
}

Eigen::Isometry3d TargetAdjustment::CameraFromTarget(int camera, int placement) const {
  const Eigen::Isometry3d first = IsometryFromPose(first_from_target.at(placement));
  return camera == 0 ? first : SecondFromFirst() * first;
}

Eigen::Isometry3d TargetAdjustment::SecondFromFirst() const {
  return IsometryFromPose(second_from_first);
}

CameraIntrinsics TargetAdjustment::Intrinsics(int camera) const {
  return CameraIntrinsics::FromParameters(intrinsics[camera], cameras[camera].width_px,
                                          cameras[camera].height_px, 0.0);
}

int TargetAdjustment::FreeParameters() const {
  const std::vector<char> adjusted = AdjustedPoints(*this);
  int n = 6 * static_cast<int>(first_from_target.size()) + (cameras.size() == 2 ? 6 : 0) +
          3 * static_cast<int>(std::count(adjusted.begin(), adjusted.end(), 1));
  for (const auto& f : fixed) n += static_cast<int>(std::count(f.begin(), f.end(), false));
  return n;
}

Status InitialiseTargetAdjustment(TargetAdjustment* a,
                                  const std::vector<const CameraIntrinsics*>& given) {
  if (a->cameras.empty() || a->cameras.size() > 2) return Error{"one or two cameras are needed"};
  if (a->cameras.size() == 2 && a->cameras[1].target != a->cameras[0].target)
    return Error{"the two cameras must see one target"};
  a->target = a->cameras[0].target;
  a->image_sigma_px = a->cameras[0].pixel_sigma_px;
  a->intrinsics.resize(a->cameras.size());
  a->fixed.resize(a->cameras.size());
  a->unresected.assign(a->cameras.size(), {});
  std::vector<std::map<int, Eigen::Isometry3d>> poses(a->cameras.size());
  for (size_t c = 0; c < a->cameras.size(); ++c) {
    const TargetViews& views = a->cameras[c];
    if (Status s = views.Check(); !s) return s;
    if (c < given.size() && given[c]) {
      a->intrinsics[c] = given[c]->ToParameters();
    } else if (!views.Planar()) {
      return Error{"a 3D target needs a starting camera (the design values)"};
    } else if (Status s = ZhangStart(views, &a->intrinsics[c]); !s) {
      return s;
    }
    if (Status s = ResectViews(&a->cameras[c], a->intrinsics[c], &poses[c], &a->unresected[c]); !s)
      return s;
  }
  a->first_from_target.clear();
  for (const auto& [placement, pose] : poses[0])
    a->first_from_target[placement] = PoseFromIsometry(pose);
  if (a->cameras.size() == 2) {
    Eigen::Isometry3d relative;
    if (Status s = StartRelativeOrientation(poses[0], poses[1], &relative); !s) return s;
    a->second_from_first = PoseFromIsometry(relative);
    for (const auto& [placement, pose] : poses[1])
      if (!a->first_from_target.count(placement))
        a->first_from_target[placement] = PoseFromIsometry(relative.inverse() * pose);
  }
  a->rejected.clear();
  EnsureRejectionFlags(a);
  return {};
}

Result<AdjustmentPrecision> SolveTargetAdjustment(TargetAdjustment* a,
                                                  const TargetAdjustmentOptions& o) {
  std::string why;
  if (!o.Check(&why)) return Error{why};
  EnsureRejectionFlags(a);
  AdjustmentPrecision precision;
  for (int round = 0;; ++round) {
    ceres::Problem problem;
    AddResiduals(a, o, &problem);
    if (Status s = Solve(&problem, o, &precision.iterations); !s) return Error{s.error()};
    double image_squares = 0.0;
    if (JudgeOutliers(a, o, round < o.max_rejection_rounds, &precision, &image_squares) != 0)
      continue;
    // The images' sigma weighs the survey: estimated again until it stands.
    const double image_sigma = ImageSigmaComponent(a, &problem, precision, image_squares);
    const bool settled = image_sigma <= 0.0 || std::abs(image_sigma / a->image_sigma_px - 1) < 0.02;
    if (!settled && round < kMaxWeightRounds) {
      a->image_sigma_px = image_sigma;
      continue;
    }
    precision.determined = EstimateCovariance(a, &problem, &precision);
    return precision;
  }
}

std::vector<std::vector<std::vector<Eigen::Vector2d>>> TargetResiduals(const TargetAdjustment& a) {
  std::vector<std::vector<std::vector<Eigen::Vector2d>>> residuals(a.cameras.size());
  for (size_t c = 0; c < a.cameras.size(); ++c) {
    const CameraModel model(a.Intrinsics(static_cast<int>(c)));
    for (const TargetView& view : a.cameras[c].views) {
      const Eigen::Isometry3d pose = a.CameraFromTarget(static_cast<int>(c), view.placement);
      std::vector<Eigen::Vector2d>& out = residuals[c].emplace_back();
      for (size_t i = 0; i < view.pixels.size(); ++i) {
        Eigen::Vector2d projected;
        const bool ok = model.Project(pose * a.target[view.ids[i]], &projected);
        // A point the model cannot project counts as a gross error, not as a perfect fit.
        out.push_back(ok ? Eigen::Vector2d(view.pixels[i] - projected) : Eigen::Vector2d(1e3, 1e3));
      }
    }
  }
  return residuals;
}

namespace {

// A term fixed at zero is not known to be zero, only not to differ from it by more than about
// its sigma; the parameters correlated with it move with it. The mean squared error of the
// reduced model's estimates, with the fixed terms as large as their sigmas, is the full model's
// covariance: that is what is reported for the terms left free.
void KeepFullModelCovariance(const TargetAdjustment& a, const AdjustmentPrecision& full,
                             AdjustmentPrecision* reduced) {
  reduced->covariance = full.covariance;
  for (size_t c = 0; c < a.cameras.size(); ++c)
    for (int j = 0; j < kN; ++j)
      if (a.fixed[c][j]) {
        reduced->covariance.row(kN * c + j).setZero();
        reduced->covariance.col(kN * c + j).setZero();
      }
}

}  // namespace

Result<std::vector<std::vector<std::string>>> FixInsignificantTerms(
    TargetAdjustment* a, const TargetAdjustmentOptions& o, double t_critical,
    AdjustmentPrecision* precision) {
  std::vector<std::vector<std::string>> fixed(a->cameras.size());
  const AdjustmentPrecision full = *precision;
  while (precision->determined) {
    int worst_camera = -1, worst_term = -1;
    double worst_t = t_critical;
    for (size_t c = 0; c < a->cameras.size(); ++c)
      for (int j = 3; j < kN; ++j) {  // the distortion and affinity terms
        if (a->fixed[c][j]) continue;
        const double sigma = std::sqrt(precision->IntrinsicsCovariance(c)(j, j));
        const double t = sigma > 0.0 ? std::abs(a->intrinsics[c][j]) / sigma : 0.0;
        if (t < worst_t) worst_t = t, worst_camera = static_cast<int>(c), worst_term = j;
      }
    if (worst_term < 0) break;
    a->fixed[worst_camera][worst_term] = true;
    a->intrinsics[worst_camera][worst_term] = 0.0;
    char text[64];
    std::snprintf(text, sizeof(text), "%s (t %.1f)", CameraIntrinsics::kParameterNames[worst_term],
                  worst_t);
    fixed[worst_camera].emplace_back(text);
    // Rejections were made against the fuller model; they are judged again.
    for (auto& camera : a->rejected)
      for (auto& view : camera) std::fill(view.begin(), view.end(), 0);
    Result<AdjustmentPrecision> again = SolveTargetAdjustment(a, o);
    if (!again) return Error{again.error()};
    *precision = *again;
  }
  if (precision->determined && full.determined) KeepFullModelCovariance(*a, full, precision);
  return fixed;
}

}  // namespace ts
