#include "processing/calibration/rig_adjustment.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <set>

#include <fmt/format.h>

#include "processing/geometry/camera_model.h"

namespace ts {

namespace {

constexpr int kPanZero = 2;
constexpr int kMaxObservabilityRounds = 4;
constexpr int kMaxWeightRounds = 6;
// Observations whose 2D residual exceeds k sigma of each coordinate are rejected.
constexpr double kRejectionK = 4.0;

bool IsOffset(int i) { return (i >= 4 && i <= 6) || (i >= 8 && i <= 10); }

using KinematicsJet = ceres::Jet<double, kStageParameterCount + 2>;

// One camera at one stage pose: its place in L as jets of the stage and the pose's encoder
// corrections. The same for every tie point the camera saw there, and the most costly part of
// a residual: computed once per set of parameter values (residuals are evaluated on several
// threads, hence the lock).
class CameraPlacement {
 public:
  CameraPlacement(const Eigen::Isometry3d& s_from_camera, const RigPose& pose)
      : s_from_camera_(s_from_camera), pose_(pose) {
    key_.fill(std::numeric_limits<double>::quiet_NaN());
  }
  void Get(const double* stage, const double* encoder, Eigen::Matrix<KinematicsJet, 3, 3>* r_lc,
           Eigen::Matrix<KinematicsJet, 3, 1>* t_lc) {
    std::array<double, kStageParameterCount + 2> key;
    std::copy(stage, stage + kStageParameterCount, key.begin());
    key[kStageParameterCount] = encoder[0];
    key[kStageParameterCount + 1] = encoder[1];
    std::lock_guard lock(mutex_);
    if (key != key_) {
      std::array<KinematicsJet, kStageParameterCount> v;
      for (int i = 0; i < kStageParameterCount; ++i) v[i] = KinematicsJet(stage[i], i);
      const KinematicsJet pan(pose_.pan_deg + encoder[0], kStageParameterCount);
      const KinematicsJet tilt(pose_.tilt_deg + encoder[1], kStageParameterCount + 1);
      Eigen::Matrix<KinematicsJet, 3, 3> r_ls;
      Eigen::Matrix<KinematicsJet, 3, 1> t_ls;
      LFromSOf(v.data(), pan, tilt, &r_ls, &t_ls);
      r_lc_ = r_ls * s_from_camera_.linear().cast<KinematicsJet>();
      t_lc_ = r_ls * s_from_camera_.translation().cast<KinematicsJet>() + t_ls;
      key_ = key;
    }
    *r_lc = r_lc_;
    *t_lc = t_lc_;
  }

 private:
  const Eigen::Isometry3d s_from_camera_;
  const RigPose pose_;
  std::mutex mutex_;
  std::array<double, kStageParameterCount + 2> key_;
  Eigen::Matrix<KinematicsJet, 3, 3> r_lc_;
  Eigen::Matrix<KinematicsJet, 3, 1> t_lc_;
};

// Each camera at each pose of the input: [2 * pose + side].
std::vector<std::shared_ptr<CameraPlacement>> Placements(const RigAdjustmentInput& in) {
  std::vector<std::shared_ptr<CameraPlacement>> placements;
  for (const RigPose& pose : in.poses)
    for (Side side : {Side::kLeft, Side::kRight})
      placements.push_back(std::make_shared<CameraPlacement>(
          side == Side::kLeft ? in.calibration.rig.SFromLeftCamera()
                              : in.calibration.rig.SFromRightCamera(),
          pose));
  return placements;
}

std::shared_ptr<CameraPlacement> PlacementOf(
    const std::vector<std::shared_ptr<CameraPlacement>>& placements, const RigTieObservation& t) {
  return placements[2 * t.pose + (t.side == Side::kLeft ? 0 : 1)];
}

// One image's measurement of a tie point. The stage's kinematics are differentiated by Ceres'
// jets, the projection (which inverts the distortion by Newton's method) analytically.
class TieCost : public ceres::SizedCostFunction<2, kStageParameterCount, 2, 3> {
 public:
  TieCost(const Calibration& calibration, const RigTieObservation& t,
          std::shared_ptr<CameraPlacement> placement, double sigma_px)
      : placement_(std::move(placement)),
        model_(t.side == Side::kLeft ? calibration.rig.left : calibration.rig.right),
        pixel_(t.pixel),
        sigma_px_(sigma_px) {}

  // Parameters: the stage vector, the encoder corrections (deg), the point in L.
  bool Evaluate(double const* const* x, double* residual, double** jacobians) const override {
    using Jet = KinematicsJet;
    Eigen::Matrix<Jet, 3, 3> r_lc;
    Eigen::Matrix<Jet, 3, 1> t_lc;
    placement_->Get(x[0], x[1], &r_lc, &t_lc);
    const Eigen::Matrix<Jet, 3, 1> point{Jet(x[2][0]), Jet(x[2][1]), Jet(x[2][2])};
    const Eigen::Matrix<Jet, 3, 1> in_camera = r_lc.transpose() * (point - t_lc);
    const Eigen::Vector3d p(in_camera[0].a, in_camera[1].a, in_camera[2].a);
    Eigen::Vector2d projected;
    CameraModel::Jacobian2x3 d_pixel;
    if (!model_.Project(p, &projected, &d_pixel)) return false;
    residual[0] = (projected.x() - pixel_.x()) / sigma_px_;
    residual[1] = (projected.y() - pixel_.y()) / sigma_px_;
    if (!jacobians) return true;
    const Eigen::Matrix<double, 2, 3> d = d_pixel / sigma_px_;
    Eigen::Matrix<double, 3, kStageParameterCount + 2> d_camera;
    for (int k = 0; k < 3; ++k) d_camera.row(k) = in_camera[k].v.transpose();
    const Eigen::Matrix<double, 2, kStageParameterCount + 2> d_angles = d * d_camera;
    using RowMajor2x14 = Eigen::Matrix<double, 2, kStageParameterCount, Eigen::RowMajor>;
    using RowMajor2x2 = Eigen::Matrix<double, 2, 2, Eigen::RowMajor>;
    using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
    if (jacobians[0]) {
      Eigen::Map<RowMajor2x14> d_stage(jacobians[0]);
      d_stage = d_angles.leftCols<kStageParameterCount>();
    }
    if (jacobians[1]) {
      Eigen::Map<RowMajor2x2> d_encoder(jacobians[1]);
      d_encoder = d_angles.rightCols<2>();
    }
    if (jacobians[2]) {
      Eigen::Matrix3d r_cl;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) r_cl(a, b) = r_lc(b, a).a;
      Eigen::Map<RowMajor2x3> d_point(jacobians[2]);
      d_point = d * r_cl;
    }
    return true;
  }

 private:
  std::shared_ptr<CameraPlacement> placement_;
  CameraModel model_;
  Eigen::Vector2d pixel_;
  double sigma_px_;
};

// Observations of parameters: (x[index] - value) / sigma for each listed index.
struct ParameterCost {
  std::vector<int> index;
  std::vector<double> value, sigma;
  template <typename T>
  bool operator()(T const* const* x, T* residual) const {
    for (size_t i = 0; i < index.size(); ++i) residual[i] = (x[0][index[i]] - value[i]) / sigma[i];
    return true;
  }
};

ceres::CostFunction* ParameterObservation(const ParameterCost& cost, int size) {
  auto* f = new ceres::DynamicAutoDiffCostFunction<ParameterCost>(new ParameterCost(cost));
  f->AddParameterBlock(size);
  f->SetNumResiduals(static_cast<int>(cost.index.size()));
  return f;
}

StageVector PriorSigmas(const RigAdjustmentOptions& o) {
  StageVector s;
  for (int i = 0; i < kStageParameterCount; ++i)
    s[i] = IsOffset(i) ? o.prior_offset_sigma_m : o.prior_angle_sigma_deg;
  return s;
}

struct Unknowns {
  StageVector stage{};
  std::vector<std::array<double, 2>> encoder;  // per pose: true minus read-back, deg
  std::vector<Eigen::Vector3d> points;
};

// `robust`: a Huber loss on the images, for the first round, before mismatched tie points are
// rejected; after it plain least squares, which converges in a few Gauss-Newton steps where
// the Huber loss's reweighting of the 3-4 sigma residuals takes a hundred.
void BuildProblem(const RigAdjustmentInput& in, const RigAdjustmentOptions& o, bool robust,
                  double pixel_sigma_px, const StageVector& prior, const std::set<int>& held,
                  const std::vector<char>& rejected, Unknowns* u, ceres::Problem* problem) {
  const std::vector<std::shared_ptr<CameraPlacement>> placements = Placements(in);
  for (size_t i = 0; i < in.observations.size(); ++i) {
    if (rejected[i]) continue;
    const RigTieObservation& t = in.observations[i];
    auto* cost = new TieCost(in.calibration, t, PlacementOf(placements, t), pixel_sigma_px);
    problem->AddResidualBlock(cost, robust ? new ceres::HuberLoss(3.0) : nullptr, u->stage.data(),
                              u->encoder[t.pose].data(), u->points[t.point].data());
  }
  for (auto& e : u->encoder)
    if (problem->HasParameterBlock(e.data()))
      problem->AddResidualBlock(
          ParameterObservation({{0, 1}, {0.0, 0.0}, {o.encoder_sigma_deg, o.encoder_sigma_deg}}, 2),
          nullptr, e.data());
  const StageVector sigma = PriorSigmas(o);
  ParameterCost prior_cost;
  for (int i = 0; i < kStageParameterCount; ++i)
    if (!held.count(i)) {
      prior_cost.index.push_back(i);
      prior_cost.value.push_back(prior[i]);
      prior_cost.sigma.push_back(sigma[i]);
    }
  problem->AddResidualBlock(ParameterObservation(prior_cost, kStageParameterCount), nullptr,
                            u->stage.data());
  if (in.inclinometer_deg && !held.count(0) && !held.count(1))
    problem->AddResidualBlock(
        ParameterObservation({{0, 1},
                              {in.inclinometer_deg->x(), in.inclinometer_deg->y()},
                              {o.inclinometer_sigma_deg, o.inclinometer_sigma_deg}},
                             kStageParameterCount),
        nullptr, u->stage.data());
  problem->SetManifold(
      u->stage.data(),
      new ceres::SubsetManifold(kStageParameterCount, std::vector<int>(held.begin(), held.end())));
}

// The robust round only has to bring the mismatched tie points out for rejection; its Huber
// loss converges slowly (see BuildProblem), and the rounds after it finish the solution.
Status Solve(bool robust, ceres::Problem* problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = robust ? 10 : 100;
  options.function_tolerance = 1e-8;
  options.parameter_tolerance = 1e-9;
  // One thread: a threaded evaluation sums in the order the threads finish, and the incremental
  // station must give the products of `process` to the bit.
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  if (!summary.IsSolutionUsable()) return Error{"the adjustment failed: " + summary.message};
  return {};
}

// The stage parameters' covariance (a priori scale; zero rows for held ones), or nothing when
// the normal matrix is singular. The points are eliminated block by block (each residual
// block of a tie observation holds one point), so the work grows with the observations, not
// with the cube of the unknowns as a QR of the whole Jacobian does.
std::optional<Eigen::MatrixXd> StageCovariance(Unknowns* u, const std::set<int>& held,
                                               ceres::Problem* problem) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks.push_back(u->stage.data());
  for (auto& e : u->encoder)
    if (problem->HasParameterBlock(e.data())) options.parameter_blocks.push_back(e.data());
  const int reduced = kStageParameterCount - static_cast<int>(held.size()) +
                      2 * (static_cast<int>(options.parameter_blocks.size()) - 1);
  // A point whose observations were all rejected has left the problem.
  std::vector<int> column_point;
  for (size_t p = 0; p < u->points.size(); ++p)
    if (problem->HasParameterBlock(u->points[p].data())) {
      options.parameter_blocks.push_back(u->points[p].data());
      column_point.push_back(static_cast<int>(p));
    }
  options.apply_loss_function = true;
  ceres::CRSMatrix j;
  if (!problem->Evaluate(options, nullptr, nullptr, nullptr, &j)) return std::nullopt;
  // Each row holds at most one point's columns: the normal matrix's blocks gathered per point,
  // then the points eliminated (Schur complement).
  const int points = static_cast<int>(column_point.size());
  Eigen::MatrixXd n_ss = Eigen::MatrixXd::Zero(reduced, reduced);
  std::vector<Eigen::Matrix3d> n_pp(points, Eigen::Matrix3d::Zero());
  std::vector<Eigen::MatrixXd> n_ps(points, Eigen::MatrixXd::Zero(3, reduced));
  Eigen::VectorXd a(reduced);
  for (int row = 0; row < j.num_rows; ++row) {
    a.setZero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    int point = -1;
    for (int k = j.rows[row]; k < j.rows[row + 1]; ++k) {
      if (j.cols[k] < reduced) {
        a[j.cols[k]] = j.values[k];
      } else {
        point = (j.cols[k] - reduced) / 3;
        b[(j.cols[k] - reduced) % 3] = j.values[k];
      }
    }
    n_ss += a * a.transpose();
    if (point < 0) continue;
    n_pp[point] += b * b.transpose();
    n_ps[point] += b * a.transpose();
  }
  for (int p = 0; p < points; ++p) {
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(n_pp[p]);
    if (!lu.isInvertible()) return std::nullopt;
    n_ss -= n_ps[p].transpose() * lu.solve(n_ps[p]);
  }
  // Inverted with its diagonal scaled to one: offsets in metres and angles in degrees differ
  // by many orders in their information.
  const Eigen::VectorXd scale = n_ss.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * n_ss * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  if (eigen.info() != Eigen::Success || !(eigen.eigenvalues()[0] > 1e-12)) return std::nullopt;
  const Eigen::MatrixXd inverse =
      scale.asDiagonal() *
      (eigen.eigenvectors() * eigen.eigenvalues().cwiseInverse().asDiagonal() *
       eigen.eigenvectors().transpose()) *
      scale.asDiagonal();
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(kStageParameterCount, kStageParameterCount);
  std::vector<int> free;
  for (int i = 0; i < kStageParameterCount; ++i)
    if (!held.count(i)) free.push_back(i);
  for (size_t r = 0; r < free.size(); ++r)
    for (size_t c = 0; c < free.size(); ++c) covariance(free[r], free[c]) = inverse(r, c);
  return covariance;
}

// The free parameters that dominate a combination the data tell less of than the prior did.
std::vector<int> Undetermined(const Eigen::MatrixXd& covariance, const std::set<int>& held,
                              const RigAdjustmentOptions& o, std::vector<std::string>* why) {
  std::vector<int> free;
  for (int i = 0; i < kStageParameterCount; ++i)
    if (!held.count(i)) free.push_back(i);
  const int n = static_cast<int>(free.size());
  const StageVector sigma = PriorSigmas(o);
  Eigen::MatrixXd c(n, n);
  Eigen::VectorXd d(n);
  for (int a = 0; a < n; ++a) {
    d[a] = sigma[free[a]];
    for (int b = 0; b < n; ++b) c(a, b) = covariance(free[a], free[b]);
  }
  // The information the data add, in units of the prior's: D (C^-1 - P^-1) D.
  const Eigen::MatrixXd scaled =
      d.asDiagonal() * c.inverse() * d.asDiagonal() - Eigen::MatrixXd::Identity(n, n);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (scaled + scaled.transpose()));
  std::vector<int> named;
  for (int k = 0; k < n; ++k) {
    if (eigen.eigenvalues()[k] >= 1.0) continue;
    Eigen::Index dominant = 0;
    eigen.eigenvectors().col(k).cwiseAbs().maxCoeff(&dominant);
    const int parameter = free[dominant];
    if (std::find(named.begin(), named.end(), parameter) != named.end()) continue;
    named.push_back(parameter);
    why->push_back(std::string(kStageParameterNames[parameter]) +
                   ": not determined by this panorama (the data add " +
                   fmt::format("{:.2g}", std::max(0.0, eigen.eigenvalues()[k])) +
                   " of the prior's information), held at its prior");
  }
  return named;
}

Status CheckInput(const RigAdjustmentInput& in) {
  if (in.poses.empty() || in.points.empty() || in.observations.empty())
    return Error{"no tie points"};
  std::vector<std::set<int>> poses_of(in.points.size());
  for (const RigTieObservation& t : in.observations) {
    if (t.pose < 0 || t.pose >= static_cast<int>(in.poses.size()) || t.point < 0 ||
        t.point >= static_cast<int>(in.points.size()) || !t.pixel.allFinite())
      return Error{"a tie observation names no pose or point, or its pixel is not finite"};
    poses_of[t.point].insert(t.pose);
  }
  for (const auto& poses : poses_of)
    if (poses.size() >= 2) return {};
  return Error{"no point is seen from two stage poses: nothing ties the poses together"};
}

}  // namespace

// Each image observation's residual (pixels), squared.
std::vector<double> SquaredResiduals(const RigAdjustmentInput& in, const Unknowns& u) {
  const std::vector<std::shared_ptr<CameraPlacement>> placements = Placements(in);
  std::vector<double> squares;
  for (const RigTieObservation& t : in.observations) {
    double residual[2] = {1e30, 1e30};
    const double* x[] = {u.stage.data(), u.encoder[t.pose].data(), u.points[t.point].data()};
    TieCost(in.calibration, t, PlacementOf(placements, t), 1.0).Evaluate(x, residual, nullptr);
    squares.push_back(residual[0] * residual[0] + residual[1] * residual[1]);
  }
  return squares;
}

// Marks the observations off by more than k sigma (a mismatched tie point), and every
// observation of a point that no longer ties two poses (its position would be free along a
// ray); true when the marks changed.
bool Reject(const RigAdjustmentInput& in, const std::vector<double>& squares, double sigma,
            std::vector<char>* rejected) {
  std::vector<char> marks(squares.size());
  std::vector<std::set<int>> poses_of(in.points.size());
  for (size_t i = 0; i < squares.size(); ++i) {
    marks[i] = squares[i] > 2.0 * std::pow(kRejectionK * sigma, 2);
    if (!marks[i]) poses_of[in.observations[i].point].insert(in.observations[i].pose);
  }
  for (size_t i = 0; i < squares.size(); ++i)
    if (poses_of[in.observations[i].point].size() < 2) marks[i] = 1;
  const bool changed = marks != *rejected;
  *rejected = std::move(marks);
  return changed;
}

Result<RigAdjustment> AdjustRig(const RigAdjustmentInput& in, const RigAdjustmentOptions& o) {
  std::string why;
  if (!o.Check(&why)) return Error{"rig adjustment: " + why};
  if (Status s = CheckInput(in); !s) return Error{"rig adjustment: " + s.error()};
  const StageVector prior = StageVectorOf(in.calibration.stage);
  std::set<int> held = {kPanZero};
  RigAdjustment r;
  Unknowns u;
  // The images' sigma is estimated as a variance component, so that the sigmas weigh the
  // images against the encoders and the inclinometer by what the images really show.
  double pixel_sigma = o.pixel_sigma_px;
  u.stage = prior;
  u.encoder.assign(in.poses.size(), {0.0, 0.0});
  u.points = in.points;
  std::vector<char> rejected(in.observations.size(), 0);
  // Each round starts from the last one's solution, a newly held parameter from its prior.
  for (int weighing = 0, observability = 0;;) {
    for (int i : held) u.stage[i] = prior[i];
    ceres::Problem problem;
    const bool robust = weighing == 0 && observability == 0;
    BuildProblem(in, o, robust, pixel_sigma, prior, held, rejected, &u, &problem);
    const std::vector<char> problem_rejected = rejected;
    if (Status s = Solve(robust, &problem); !s) return Error{"rig adjustment: " + s.error()};
    const std::vector<double> squared = SquaredResiduals(in, u);
    double squares = 0.0;
    int kept = 0, coordinates = 0;
    std::set<int> points;
    for (size_t i = 0; i < squared.size(); ++i)
      if (!rejected[i]) {
        squares += squared[i], ++kept;
        coordinates += in.observations[i].along_epipolar_only ? 1 : 2;
        points.insert(in.observations[i].point);
      }
    const int free = kStageParameterCount - static_cast<int>(held.size());
    const int redundancy = coordinates - 3 * static_cast<int>(points.size()) - free;
    if (redundancy <= 0) return Error{"rig adjustment: fewer observations than unknowns"};
    const double image_sigma = std::sqrt(squares / redundancy);
    const bool reweigh = std::abs(image_sigma / pixel_sigma - 1.0) > 0.05;
    const bool marks_changed = Reject(in, squared, image_sigma, &rejected);
    if ((reweigh || marks_changed) && weighing++ < kMaxWeightRounds) {
      pixel_sigma = image_sigma;
      continue;
    }
    r.observations = kept;
    r.rejected_observation = problem_rejected;
    r.rejected = static_cast<int>(in.observations.size()) - kept;
    const std::optional<Eigen::MatrixXd> covariance = StageCovariance(&u, held, &problem);
    if (!covariance) return Error{"rig adjustment: the covariance of the stage cannot be computed"};
    std::vector<std::string> reasons;
    const std::vector<int> named = Undetermined(*covariance, held, o, &reasons);
    if (!named.empty() && observability++ < kMaxObservabilityRounds) {
      held.insert(named.begin(), named.end());
      r.undetermined.insert(r.undetermined.end(), reasons.begin(), reasons.end());
      continue;
    }
    r.rms_px = std::sqrt(squares / (2.0 * kept));
    r.image_sigma_px = image_sigma;
    for (int i = 0; i < kStageParameterCount; ++i)
      r.sigma[i] = held.count(i) ? 0.0 : std::sqrt((*covariance)(i, i));
    r.stage = StageKinematicsOf(u.stage, in.calibration.stage);
    r.points = u.points;
    return r;
  }
}

}  // namespace ts
