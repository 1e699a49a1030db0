#include "processing/calibration/rig_adjustment.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <set>

#include <fmt/format.h>

#include "processing/calibration/rig_cameras.h"
#include "processing/common/median.h"
#include "processing/geometry/camera_model.h"

namespace ts {

namespace {

constexpr int kPanZero = 2;
constexpr int kMaxObservabilityRounds = 4;
constexpr int kMaxWeightRounds = 6;
// Observations whose 2D residual exceeds k sigma of each coordinate are rejected.
constexpr double kRejectionK = 4.0;

bool IsOffset(int i) { return (i >= 4 && i <= 6) || (i >= 8 && i <= 10); }
bool IsRigMount(int i) { return i >= 11 && i <= 13; }  // the rig's omega, phi, kappa

// The adjustment's parameters as one list: the shared stage's (kStageParameterCount; its
// levelling is not used, each station has its own), then each station's levelling.
int LevellingParameter(int station, int axis) { return kStageParameterCount + 2 * station + axis; }

std::string ParameterName(int i, int stations) {
  if (i < kStageParameterCount) return kStageParameterNames[i];
  const int station = (i - kStageParameterCount) / 2;
  return std::string(kStageParameterNames[i % 2]) +
         (stations > 1 ? fmt::format(" of station {}", station + 1) : "");
}

// Jet slots: the station's levelling in the stage's levelling slots (0, 1), the rest of the
// stage, then the encoder corrections.
using KinematicsJet = ceres::Jet<double, kStageParameterCount + 2>;

// S in L at one stage pose, as jets of the stage, the station's levelling and the pose's
// encoder corrections. The same for every tie point seen there, and the most costly part of a
// residual: computed once per set of parameter values (residuals may be evaluated on several
// threads, hence the lock).
class StagePlacement {
 public:
  explicit StagePlacement(const RigPose& pose) : pose_(pose) {
    key_.fill(std::numeric_limits<double>::quiet_NaN());
  }
  void Get(const double* stage, const double* levelling, const double* encoder,
           Eigen::Matrix<KinematicsJet, 3, 3>* r_ls, Eigen::Matrix<KinematicsJet, 3, 1>* t_ls) {
    std::array<double, kStageParameterCount + 2> key;
    std::copy(stage, stage + kStageParameterCount, key.begin());
    key[0] = levelling[0];
    key[1] = levelling[1];
    key[kStageParameterCount] = encoder[0];
    key[kStageParameterCount + 1] = encoder[1];
    std::lock_guard lock(mutex_);
    if (key != key_) {
      std::array<KinematicsJet, kStageParameterCount> v;
      for (int i = 0; i < kStageParameterCount; ++i) v[i] = KinematicsJet(key[i], i);
      const KinematicsJet pan(pose_.pan_deg + encoder[0], kStageParameterCount);
      const KinematicsJet tilt(pose_.tilt_deg + encoder[1], kStageParameterCount + 1);
      LFromSOf(v.data(), pan, tilt, &r_ls_, &t_ls_);
      key_ = key;
    }
    *r_ls = r_ls_;
    *t_ls = t_ls_;
  }

 private:
  const RigPose pose_;
  std::mutex mutex_;
  std::array<double, kStageParameterCount + 2> key_;
  Eigen::Matrix<KinematicsJet, 3, 3> r_ls_;
  Eigen::Matrix<KinematicsJet, 3, 1> t_ls_;
};

// The stage at each pose and each camera in the rig, shared by the observations.
struct Placements {
  std::vector<std::shared_ptr<StagePlacement>> stage;  // per pose
  std::array<std::shared_ptr<CameraInRig>, 2> camera;  // left, right
  explicit Placements(const RigAdjustmentInput& in) {
    for (const RigPose& pose : in.poses) stage.push_back(std::make_shared<StagePlacement>(pose));
    for (Side side : {Side::kLeft, Side::kRight})
      camera[side == Side::kLeft ? 0 : 1] =
          std::make_shared<CameraInRig>(side, in.calibration.rig.S_from_left);
  }
};

// One image's measurement of a tie point. The stage's kinematics and the camera's place in
// the rig are differentiated by Ceres' jets, the projection (which inverts the distortion by
// Newton's method) analytically.
class TieCost
    : public ceres::SizedCostFunction<2, kStageParameterCount, 2, 2, 3,
                                      CameraIntrinsics::kNumParameters, kStereoParameterCount> {
 public:
  TieCost(const Calibration& calibration, const RigTieObservation& t, const Placements& placements,
          double sigma_px)
      : stage_(placements.stage[t.pose]),
        camera_(placements.camera[t.side == Side::kLeft ? 0 : 1]),
        start_(t.side == Side::kLeft ? calibration.rig.left : calibration.rig.right),
        pixel_(t.pixel),
        sigma_px_(sigma_px) {}

  // Parameters: the stage vector, the station's levelling and the pose's encoder corrections
  // (deg), the point in L, the camera's intrinsics, the stereo pair (rig_cameras.h).
  bool Evaluate(double const* const* x, double* residual, double** jacobians) const override {
    using Jet = KinematicsJet;
    Eigen::Matrix<Jet, 3, 3> r_ls;
    Eigen::Matrix<Jet, 3, 1> t_ls;
    stage_->Get(x[0], x[1], x[2], &r_ls, &t_ls);
    Eigen::Matrix<StereoJet, 3, 3> r_sc;
    Eigen::Matrix<StereoJet, 3, 1> c_s;
    camera_->Get(x[5], &r_sc, &c_s);
    const Eigen::Matrix<Jet, 3, 1> point{Jet(x[3][0]), Jet(x[3][1]), Jet(x[3][2])};
    const Eigen::Matrix<Jet, 3, 1> in_s = r_ls.transpose() * (point - t_ls);
    const Eigen::Vector3d q(in_s[0].a, in_s[1].a, in_s[2].a);
    const Eigen::Matrix<StereoJet, 3, 1> in_camera = r_sc.transpose() * (q.cast<StereoJet>() - c_s);
    const Eigen::Vector3d p(in_camera[0].a, in_camera[1].a, in_camera[2].a);
    IntrinsicsVector intrinsics;
    std::copy(x[4], x[4] + intrinsics.size(), intrinsics.begin());
    const CameraModel model(CameraIntrinsics::FromParameters(
        intrinsics, start_.width_px, start_.height_px, start_.pixel_size_um));
    Eigen::Vector2d projected;
    CameraModel::Jacobian2x3 d_pixel;
    CameraModel::JacobianIntrinsics d_intrinsics;
    const bool want_intrinsics = jacobians && jacobians[4];
    if (!model.Project(p, &projected, &d_pixel, want_intrinsics ? &d_intrinsics : nullptr))
      return false;
    residual[0] = (projected.x() - pixel_.x()) / sigma_px_;
    residual[1] = (projected.y() - pixel_.y()) / sigma_px_;
    if (!jacobians) return true;
    const Eigen::Matrix<double, 2, 3> d = d_pixel / sigma_px_;
    Eigen::Matrix3d r_cs;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) r_cs(a, b) = r_sc(b, a).a;
    Eigen::Matrix<double, 3, kStageParameterCount + 2> d_in_s;
    for (int k = 0; k < 3; ++k) d_in_s.row(k) = in_s[k].v.transpose();
    const Eigen::Matrix<double, 2, 3> d_s = d * r_cs;  // of the pixel by the point in S
    const Eigen::Matrix<double, 2, kStageParameterCount + 2> d_angles = d_s * d_in_s;
    using RowMajor2x14 = Eigen::Matrix<double, 2, kStageParameterCount, Eigen::RowMajor>;
    using RowMajor2x2 = Eigen::Matrix<double, 2, 2, Eigen::RowMajor>;
    using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
    if (jacobians[0]) {
      Eigen::Map<RowMajor2x14> d_stage(jacobians[0]);
      d_stage = d_angles.leftCols<kStageParameterCount>();
      d_stage.leftCols<2>().setZero();  // the levelling slots are the station's
    }
    if (jacobians[1]) {
      Eigen::Map<RowMajor2x2> d_levelling(jacobians[1]);
      d_levelling = d_angles.leftCols<2>();
    }
    if (jacobians[2]) {
      Eigen::Map<RowMajor2x2> d_encoder(jacobians[2]);
      d_encoder = d_angles.rightCols<2>();
    }
    if (jacobians[3]) {
      Eigen::Matrix3d r_sl;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) r_sl(a, b) = r_ls(b, a).a;
      Eigen::Map<RowMajor2x3> d_point(jacobians[3]);
      d_point = d_s * r_sl;
    }
    if (jacobians[4]) {
      Eigen::Map<Eigen::Matrix<double, 2, CameraIntrinsics::kNumParameters, Eigen::RowMajor>>
          d_interior(jacobians[4]);
      d_interior = d_intrinsics / sigma_px_;
    }
    if (jacobians[5]) {
      Eigen::Matrix<double, 3, kStereoParameterCount> d_camera;
      for (int k = 0; k < 3; ++k) d_camera.row(k) = in_camera[k].v.transpose();
      Eigen::Map<Eigen::Matrix<double, 2, kStereoParameterCount, Eigen::RowMajor>> d_stereo(
          jacobians[5]);
      d_stereo = d * d_camera;
    }
    return true;
  }

 private:
  std::shared_ptr<StagePlacement> stage_;
  std::shared_ptr<CameraInRig> camera_;
  CameraIntrinsics start_;  // the image's size and pixel
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

// A target's surveyed coordinates as an observation of its point in L through the field's
// pose in L (angle-axis, then translation).
struct SurveyedCost {
  Eigen::Vector3d surveyed;
  double sigma_m;
  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    const T x[3] = {T(surveyed.x()), T(surveyed.y()), T(surveyed.z())};
    T in_l[3];
    ceres::AngleAxisRotatePoint(pose, x, in_l);
    for (int k = 0; k < 3; ++k) residual[k] = (point[k] - in_l[k] - pose[3 + k]) / sigma_m;
    return true;
  }
};

// An exactly surveyed target is still weighed: 0.1 mm, far below what the images resolve.
constexpr double kExactSurveySigmaM = 1e-4;
double SurveySigma(const RigControlField& field, int k) {
  return field.sigma_m[k] > 0.0 ? field.sigma_m[k] : kExactSurveySigmaM;
}

using FieldPose = std::array<double, 6>;  // L_from_field: angle-axis (rad), translation (m)

FieldPose FieldPoseOf(const Eigen::Isometry3d& l_from_field) {
  const Eigen::AngleAxisd aa(l_from_field.linear());
  const Eigen::Vector3d r = aa.angle() * aa.axis(), t = l_from_field.translation();
  return {r.x(), r.y(), r.z(), t.x(), t.y(), t.z()};
}

Eigen::Isometry3d IsometryOf(const FieldPose& pose) {
  const Eigen::Vector3d r(pose[0], pose[1], pose[2]);
  Eigen::Isometry3d l_from_field = Eigen::Isometry3d::Identity();
  if (r.norm() > 0.0) l_from_field.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).matrix();
  l_from_field.translation() = Eigen::Vector3d(pose[3], pose[4], pose[5]);
  return l_from_field;
}

ceres::CostFunction* ParameterObservation(const ParameterCost& cost, int size) {
  auto* f = new ceres::DynamicAutoDiffCostFunction<ParameterCost>(new ParameterCost(cost));
  f->AddParameterBlock(size);
  f->SetNumResiduals(static_cast<int>(cost.index.size()));
  return f;
}

std::vector<double> PriorSigmas(const RigAdjustmentOptions& o, int stations) {
  std::vector<double> s(kStageParameterCount + 2 * stations, o.prior_angle_sigma_deg);
  for (int i = 0; i < kStageParameterCount; ++i) {
    if (IsOffset(i)) s[i] = o.prior_offset_sigma_m;
    if (IsRigMount(i)) s[i] = o.prior_mount_sigma_deg;
  }
  return s;
}

struct Unknowns {
  explicit Unknowns(const StereoRig& rig) : cameras(rig) {}
  StageVector stage{};
  std::vector<std::array<double, 2>> levelling;  // per station, deg
  std::vector<std::array<double, 2>> encoder;    // per pose: true minus read-back, deg
  std::vector<Eigen::Vector3d> points;
  std::vector<FieldPose> field_pose;  // per control field
  RigCameraUnknowns cameras;
  double* BlockOf(int i) {
    return i < kStageParameterCount ? stage.data()
                                    : levelling[(i - kStageParameterCount) / 2].data();
  }
  double& Parameter(int i) { return BlockOf(i)[i < kStageParameterCount ? i : i % 2]; }
};

// The images' sigma, one per kind of image observation: a panorama's tie points and a control
// field's targets are measured by different means (matching, a disc's centre), each weighed
// by what it shows.
struct ImageSigmas {
  std::array<double, 2> sigma{};  // tie points, targets
  double Of(bool target) const { return sigma[target ? 1 : 0]; }
};

// Each observation's sigma relative to its kind's image sigma: a measurement's own sigma over
// the median of its kind's own sigmas, 1 for one without (RigTieObservation::
// measured_sigma_px). The image sigma, a variance component, then scales them all.
std::vector<double> RelativeSigmas(const RigAdjustmentInput& in, const std::vector<char>& control) {
  std::array<std::vector<double>, 2> measured;
  for (const RigTieObservation& t : in.observations)
    if (t.measured_sigma_px > 0.0)
      measured[control[t.point] ? 1 : 0].push_back(t.measured_sigma_px);
  const std::array<double, 2> median = {Median(measured[0]), Median(measured[1])};
  std::vector<double> relative(in.observations.size(), 1.0);
  for (size_t i = 0; i < in.observations.size(); ++i) {
    const RigTieObservation& t = in.observations[i];
    if (t.measured_sigma_px > 0.0)
      relative[i] = t.measured_sigma_px / median[control[t.point] ? 1 : 0];
  }
  return relative;
}

// The image observations' sums, per kind.
struct ImageSums {
  std::array<double, 2> squares{};        // each over its relative sigma squared
  std::array<double, 2> pixel_squares{};  // as they are
  std::array<int, 2> kept{}, coordinates{};
  std::array<std::set<int>, 2> points;
};

// `squared`: each observation's squared residual in pixels (SquaredResiduals).
ImageSums SumImageResiduals(const RigAdjustmentInput& in, const std::vector<char>& control,
                            const std::vector<double>& relative_sigma,
                            const std::vector<double>& squared, const std::vector<char>& rejected) {
  ImageSums sums;
  for (size_t i = 0; i < squared.size(); ++i) {
    if (rejected[i]) continue;
    const RigTieObservation& t = in.observations[i];
    const int kind = control[t.point] ? 1 : 0;
    sums.squares[kind] += squared[i] / (relative_sigma[i] * relative_sigma[i]);
    sums.pixel_squares[kind] += squared[i];
    ++sums.kept[kind];
    sums.coordinates[kind] += t.along_epipolar_only ? 1 : 2;
    sums.points[kind].insert(t.point);
  }
  return sums;
}

// Each kind's sigma as a variance component: its squared residuals over its redundancy, the
// parameters shared out by the kinds' numbers of coordinates (a few dozen against thousands of
// coordinates), the targets' with what their surveyed coordinates add. Nothing when a kind has
// no redundancy.
std::optional<ImageSigmas> EstimateImageSigmas(const ImageSums& sums, int parameters,
                                               int survey_redundancy, const ImageSigmas& last) {
  const double coordinates = sums.coordinates[0] + sums.coordinates[1];
  ImageSigmas estimate = last;
  for (int kind : {0, 1}) {
    if (sums.kept[kind] == 0) continue;
    const double redundancy =
        sums.coordinates[kind] - 3.0 * static_cast<double>(sums.points[kind].size()) -
        parameters * sums.coordinates[kind] / coordinates + (kind == 1 ? survey_redundancy : 0);
    if (redundancy <= 0.0) return std::nullopt;
    estimate.sigma[kind] = std::sqrt(sums.squares[kind] / redundancy);
  }
  return estimate;
}

// `robust`: a Huber loss on the images, for the first round, before mismatched tie points are
// rejected; after it plain least squares, which converges in a few Gauss-Newton steps where
// the Huber loss's reweighting of the 3-4 sigma residuals takes a hundred. `control`:
// in.ControlPoints().
Status BuildProblem(const RigAdjustmentInput& in, const std::vector<char>& control,
                    const std::vector<double>& relative_sigma, const RigAdjustmentOptions& o,
                    bool robust, const ImageSigmas& pixel_sigma, const std::vector<double>& prior,
                    const std::set<int>& held, const std::vector<char>& rejected, Unknowns* u,
                    ceres::Problem* problem) {
  const Placements placements(in);
  for (size_t i = 0; i < in.observations.size(); ++i) {
    if (rejected[i]) continue;
    const RigTieObservation& t = in.observations[i];
    auto* cost = new TieCost(in.calibration, t, placements,
                             pixel_sigma.Of(control[t.point]) * relative_sigma[i]);
    problem->AddResidualBlock(
        cost, robust ? new ceres::HuberLoss(3.0) : nullptr,
        {u->stage.data(), u->levelling[in.poses[t.pose].station].data(), u->encoder[t.pose].data(),
         u->points[t.point].data(), u->cameras.Intrinsics(t.side), u->cameras.stereo.data()});
  }
  // A target whose image observations were all rejected has left the problem.
  for (size_t f = 0; f < in.control_fields.size(); ++f) {
    const RigControlField& field = in.control_fields[f];
    for (size_t k = 0; k < field.points.size(); ++k) {
      double* point = u->points[field.points[k]].data();
      if (!problem->HasParameterBlock(point)) continue;
      problem->AddResidualBlock(
          new ceres::AutoDiffCostFunction<SurveyedCost, 3, 6, 3>(
              new SurveyedCost{field.surveyed[k], SurveySigma(field, static_cast<int>(k))}),
          nullptr, u->field_pose[f].data(), point);
    }
  }
  for (auto& e : u->encoder)
    if (problem->HasParameterBlock(e.data()))
      problem->AddResidualBlock(
          ParameterObservation({{0, 1}, {0.0, 0.0}, {o.encoder_sigma_deg, o.encoder_sigma_deg}}, 2),
          nullptr, e.data());
  const std::vector<RigStation> stations = in.Stations();
  const std::vector<double> sigma = PriorSigmas(o, static_cast<int>(stations.size()));
  // The prior of each block's free parameters, observed as parameters of that block.
  const auto add_prior = [&](double* block, int first, int size) {
    ParameterCost cost;
    std::vector<int> constant;
    for (int k = 0; k < size; ++k) {
      if (held.count(first + k)) {
        constant.push_back(k);
        continue;
      }
      cost.index.push_back(k);
      cost.value.push_back(prior[first + k]);
      cost.sigma.push_back(sigma[first + k]);
    }
    if (cost.index.empty()) {
      problem->SetParameterBlockConstant(block);
      return;
    }
    problem->AddResidualBlock(ParameterObservation(cost, size), nullptr, block);
    if (!constant.empty()) problem->SetManifold(block, new ceres::SubsetManifold(size, constant));
  };
  add_prior(u->stage.data(), 0, kStageParameterCount);
  for (size_t s = 0; s < stations.size(); ++s) {
    double* levelling = u->levelling[s].data();
    if (!problem->HasParameterBlock(levelling)) continue;
    const int x = LevellingParameter(static_cast<int>(s), 0);
    const double inclinometer_sigma = stations[s].inclinometer_sigma_deg > 0.0
                                          ? stations[s].inclinometer_sigma_deg
                                          : o.inclinometer_sigma_deg;
    if (stations[s].inclinometer_deg && !held.count(x) && !held.count(x + 1))
      problem->AddResidualBlock(ParameterObservation({{0, 1},
                                                      {stations[s].inclinometer_deg->x(),
                                                       stations[s].inclinometer_deg->y()},
                                                      {inclinometer_sigma, inclinometer_sigma}},
                                                     2),
                                nullptr, levelling);
    add_prior(levelling, x, 2);
  }
  return AddCameraPriors(in.calibration, o.refine_cameras, &u->cameras, problem);
}

// The robust round only has to bring the mismatched tie points out for rejection; its Huber
// loss converges slowly (see BuildProblem), and the rounds after it finish the solution.
Status Solve(bool robust, ceres::Problem* problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = robust ? 4 : 100;
  // Without the robust loss the problem is nearly linear, and each round starts from the last
  // one's solution: Gauss-Newton steps (a wide trust region) converge in one or two iterations
  // where Levenberg-Marquardt's default damping takes five or six.
  if (!robust) options.initial_trust_region_radius = 1e8;
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

// The parameters free in the problem, in the order of the Jacobian's columns: a station's
// levelling whose block left the problem (its tie points all rejected) is not.
std::vector<int> FreeParameters(Unknowns* u, const std::set<int>& held, ceres::Problem* problem) {
  std::vector<int> free;
  for (int i = 0; i < kStageParameterCount + 2 * static_cast<int>(u->levelling.size()); ++i)
    if (!held.count(i) && problem->HasParameterBlock(u->BlockOf(i))) free.push_back(i);
  return free;
}

// The cameras' refined parameters (rig_cameras.h's list) in the problem, in the order of the
// Jacobian's columns; none when the cameras are held.
std::vector<int> FreeCameraParameters(const Calibration& calibration, bool refine, Unknowns* u,
                                      ceres::Problem* problem) {
  std::vector<int> free;
  if (!refine) return free;
  for (int i : RefinedCameraParameters(calibration))
    if (problem->HasParameterBlock(u->cameras.Blocks()[CameraBlockOf(i)])) free.push_back(i);
  return free;
}

// The covariances a posteriori (a priori scale; zero rows for held parameters): the stage's
// and the stations' levellings' (LevellingParameter's list) from the data, the cameras'
// (rig_cameras.h's); and what held cameras' errors add to the stage's.
struct ParameterCovariances {
  Eigen::MatrixXd stage, cameras, stage_from_held_cameras;
};

// The camera blocks held in the problem, and the list's indices (rig_cameras.h's) of their
// parameters in the order of their columns.
struct HeldCameras {
  std::vector<double*> blocks;
  std::vector<int> parameters;
};
HeldCameras HeldCameraBlocks(Unknowns* u, ceres::Problem* problem) {
  HeldCameras held;
  const std::array<double*, 3> blocks = u->cameras.Blocks();
  for (int b = 0; b < 3; ++b) {
    if (!problem->HasParameterBlock(blocks[b]) || !problem->IsParameterBlockConstant(blocks[b]))
      continue;
    held.blocks.push_back(blocks[b]);
    for (int i = 0; i < kCameraBlockSize[b]; ++i)
      held.parameters.push_back(kCameraBlockFirst[b] + i);
  }
  return held;
}

// Held cameras are not exact: a calibration's error dc moves the stage's estimate by
// dx = -N_xx^-1 N_xc dc, which the data's covariance N_xx^-1 leaves out. With dc's covariance
// C (the calibration's), the stage's gains K C K^T, K = N_xx^-1 N_xc: the "consider"
// covariance of a parameter held at an uncertain value.
Eigen::MatrixXd ConsideredCovariance(const Eigen::MatrixXd& inverse, const Eigen::MatrixXd& n_xc,
                                     const Eigen::MatrixXd& c) {
  const Eigen::MatrixXd k = inverse * n_xc;
  return k * c * k.transpose();
}

// Nothing when the normal matrix is singular. The points are eliminated block by block (each
// residual block of a tie observation holds one point), so the work grows with the
// observations, not with the cube of the unknowns as a QR of the whole Jacobian does.
// `held_camera_covariance`: of the held cameras (RigCameraCovariance), empty when they are
// refined.
std::optional<ParameterCovariances> ParameterCovariance(
    Unknowns* u, const std::vector<int>& free, const std::vector<int>& camera_free,
    const Eigen::MatrixXd& held_camera_covariance, ceres::Problem* problem) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks.push_back(u->stage.data());
  for (auto& l : u->levelling)
    if (problem->HasParameterBlock(l.data()) && !problem->IsParameterBlockConstant(l.data()))
      options.parameter_blocks.push_back(l.data());
  int encoders = 0;
  for (auto& e : u->encoder)
    if (problem->HasParameterBlock(e.data())) {
      options.parameter_blocks.push_back(e.data());
      ++encoders;
    }
  int field_parameters = 0;
  for (auto& f : u->field_pose)
    if (problem->HasParameterBlock(f.data())) {
      options.parameter_blocks.push_back(f.data());
      field_parameters += 6;
    }
  std::set<int> camera_blocks;
  for (int i : camera_free) camera_blocks.insert(CameraBlockOf(i));
  for (int b : camera_blocks) options.parameter_blocks.push_back(u->cameras.Blocks()[b]);
  const int first_camera = static_cast<int>(free.size()) + 2 * encoders + field_parameters;
  const int estimated = first_camera + static_cast<int>(camera_free.size());
  // Held cameras' columns follow, for their errors' share (ConsideredCovariance); Evaluate
  // differentiates only variable blocks.
  const HeldCameras held_cameras =
      held_camera_covariance.size() > 0 ? HeldCameraBlocks(u, problem) : HeldCameras();
  for (double* block : held_cameras.blocks) {
    options.parameter_blocks.push_back(block);
    problem->SetParameterBlockVariable(block);
  }
  const int reduced = estimated + static_cast<int>(held_cameras.parameters.size());
  // A point whose observations were all rejected has left the problem.
  std::vector<int> column_point;
  for (size_t p = 0; p < u->points.size(); ++p)
    if (problem->HasParameterBlock(u->points[p].data())) {
      options.parameter_blocks.push_back(u->points[p].data());
      column_point.push_back(static_cast<int>(p));
    }
  options.apply_loss_function = true;
  ceres::CRSMatrix j;
  const bool evaluated = problem->Evaluate(options, nullptr, nullptr, nullptr, &j);
  for (double* block : held_cameras.blocks) problem->SetParameterBlockConstant(block);
  if (!evaluated) return std::nullopt;
  // Each row holds at most one point's columns: the normal matrix's blocks gathered per point,
  // then the points eliminated (Schur complement).
  const int points = static_cast<int>(column_point.size());
  Eigen::MatrixXd n_ss = Eigen::MatrixXd::Zero(reduced, reduced);
  std::vector<Eigen::Matrix3d> n_pp(points, Eigen::Matrix3d::Zero());
  std::vector<Eigen::MatrixXd> n_ps(points, Eigen::MatrixXd::Zero(3, reduced));
  // A row touches the stage, one pose's encoders and levelling, and one point: its products are
  // summed over the columns it touches only (the others add zeros), and each point's block is
  // eliminated over the columns its rows touched.
  std::vector<std::vector<int>> point_columns(points);
  std::vector<int> columns;
  std::vector<double> values;
  for (int row = 0; row < j.num_rows; ++row) {
    columns.clear();
    values.clear();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    int point = -1;
    for (int k = j.rows[row]; k < j.rows[row + 1]; ++k) {
      if (j.cols[k] < reduced) {
        columns.push_back(j.cols[k]);
        values.push_back(j.values[k]);
      } else {
        point = (j.cols[k] - reduced) / 3;
        b[(j.cols[k] - reduced) % 3] = j.values[k];
      }
    }
    for (size_t x = 0; x < columns.size(); ++x)
      for (size_t y = 0; y < columns.size(); ++y)
        n_ss(columns[x], columns[y]) += values[x] * values[y];
    if (point < 0) continue;
    n_pp[point] += b * b.transpose();
    for (size_t x = 0; x < columns.size(); ++x) {
      n_ps[point].col(columns[x]) += b * values[x];
      point_columns[point].push_back(columns[x]);
    }
  }
  for (int p = 0; p < points; ++p) {
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(n_pp[p]);
    if (!lu.isInvertible()) return std::nullopt;
    std::vector<int>& touched = point_columns[p];
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    const int t = static_cast<int>(touched.size());
    Eigen::MatrixXd n_pt(3, t);
    for (int x = 0; x < t; ++x) n_pt.col(x) = n_ps[p].col(touched[x]);
    const Eigen::MatrixXd update = n_pt.transpose() * lu.solve(n_pt);
    for (int x = 0; x < t; ++x)
      for (int y = 0; y < t; ++y) n_ss(touched[x], touched[y]) -= update(x, y);
  }
  // Inverted with its diagonal scaled to one: offsets in metres and angles in degrees differ
  // by many orders in their information.
  const Eigen::MatrixXd n_xx = n_ss.topLeftCorner(estimated, estimated);
  const Eigen::VectorXd scale = n_xx.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * n_xx * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  if (eigen.info() != Eigen::Success || !(eigen.eigenvalues()[0] > 1e-12)) return std::nullopt;
  const Eigen::MatrixXd inverse =
      scale.asDiagonal() *
      (eigen.eigenvectors() * eigen.eigenvalues().cwiseInverse().asDiagonal() *
       eigen.eigenvectors().transpose()) *
      scale.asDiagonal();
  const int parameters = kStageParameterCount + 2 * static_cast<int>(u->levelling.size());
  ParameterCovariances c;
  c.stage = Eigen::MatrixXd::Zero(parameters, parameters);
  for (size_t a = 0; a < free.size(); ++a)
    for (size_t b = 0; b < free.size(); ++b) c.stage(free[a], free[b]) = inverse(a, b);
  c.cameras = Eigen::MatrixXd::Zero(kRigCameraParameterCount, kRigCameraParameterCount);
  for (size_t a = 0; a < camera_free.size(); ++a)
    for (size_t b = 0; b < camera_free.size(); ++b)
      c.cameras(camera_free[a], camera_free[b]) = inverse(first_camera + a, first_camera + b);
  c.stage_from_held_cameras = Eigen::MatrixXd::Zero(parameters, parameters);
  if (held_cameras.blocks.empty()) return c;
  const std::vector<int>& held = held_cameras.parameters;
  const Eigen::MatrixXd considered =
      ConsideredCovariance(inverse, n_ss.topRightCorner(estimated, reduced - estimated),
                           held_camera_covariance(held, held));
  for (size_t a = 0; a < free.size(); ++a)
    for (size_t b = 0; b < free.size(); ++b)
      c.stage_from_held_cameras(free[a], free[b]) = considered(a, b);
  return c;
}

// The free parameters that dominate a combination the data tell less of than the prior did.
std::vector<int> Undetermined(const Eigen::MatrixXd& covariance, const std::vector<int>& free,
                              const RigAdjustmentOptions& o, int stations,
                              std::vector<std::string>* why) {
  const int n = static_cast<int>(free.size());
  const std::vector<double> sigma = PriorSigmas(o, stations);
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
    why->push_back(ParameterName(parameter, stations) +
                   ": not determined by these views (the data add " +
                   fmt::format("{:.2g}", std::max(0.0, eigen.eigenvalues()[k])) +
                   " of the prior's information), held at its prior");
  }
  return named;
}

// What the surveyed coordinates add to the redundancy: three per target in the problem, less
// the field's pose.
int SurveyRedundancy(const RigAdjustmentInput& in, const Unknowns& u,
                     const ceres::Problem& problem) {
  int redundancy = 0;
  for (const RigControlField& field : in.control_fields) {
    int targets = 0;
    for (int point : field.points) targets += problem.HasParameterBlock(u.points[point].data());
    if (targets > 0) redundancy += 3 * targets - 6;
  }
  return redundancy;
}

// `target_sigma_px`: the targets' variance component.
std::vector<RigAdjustment::ControlFit> ControlFits(const RigAdjustmentInput& in, const Unknowns& u,
                                                   const std::vector<double>& squared,
                                                   const std::vector<char>& rejected,
                                                   double target_sigma_px) {
  std::vector<RigAdjustment::ControlFit> fits;
  for (size_t f = 0; f < in.control_fields.size(); ++f) {
    const RigControlField& field = in.control_fields[f];
    RigAdjustment::ControlFit fit;
    fit.l_from_field = IsometryOf(u.field_pose[f]);
    fit.image_sigma_px = target_sigma_px;
    std::vector<char> target(in.points.size(), 0);
    for (int point : field.points) target[point] = 1;
    std::vector<char> seen(in.points.size(), 0);
    double squares = 0.0;
    int kept = 0;
    for (size_t i = 0; i < squared.size(); ++i)
      if (!rejected[i] && target[in.observations[i].point]) {
        squares += squared[i], ++kept;
        seen[in.observations[i].point] = 1;
      }
    fit.rms_px = kept > 0 ? std::sqrt(squares / (2.0 * kept)) : 0.0;
    for (size_t k = 0; k < field.points.size(); ++k) {
      if (!seen[field.points[k]]) continue;
      ++fit.targets;
      const Eigen::Vector3d moved =
          fit.l_from_field.inverse() * u.points[field.points[k]] - field.surveyed[k];
      fit.largest_move_sigma =
          std::max(fit.largest_move_sigma,
                   moved.cwiseAbs().maxCoeff() / SurveySigma(field, static_cast<int>(k)));
    }
    fits.push_back(fit);
  }
  return fits;
}

Status CheckControlFields(const RigAdjustmentInput& in, int stations) {
  for (const RigControlField& field : in.control_fields) {
    if (field.station < 0 || field.station >= stations)
      return Error{
          fmt::format("a control field names station {} of {}", field.station + 1, stations)};
    if (field.surveyed.size() != field.points.size() || field.sigma_m.size() != field.points.size())
      return Error{"a control field's targets, coordinates and sigmas differ in number"};
    for (size_t k = 0; k < field.points.size(); ++k)
      if (field.points[k] < 0 || field.points[k] >= static_cast<int>(in.points.size()) ||
          !field.surveyed[k].allFinite() || !(field.sigma_m[k] >= 0.0))
        return Error{"a control field's target names no point, or its coordinates are not finite"};
  }
  return {};
}

// Every station needs a point seen from two of its poses; a tie point belongs to one station.
Status CheckInput(const RigAdjustmentInput& in) {
  if (in.poses.empty() || in.points.empty() || in.observations.empty())
    return Error{"no tie points"};
  const int stations = static_cast<int>(in.Stations().size());
  for (const RigPose& pose : in.poses)
    if (pose.station < 0 || pose.station >= stations)
      return Error{fmt::format("a pose names station {} of {}", pose.station + 1, stations)};
  std::vector<std::set<int>> poses_of(in.points.size());
  for (const RigTieObservation& t : in.observations) {
    if (t.pose < 0 || t.pose >= static_cast<int>(in.poses.size()) || t.point < 0 ||
        t.point >= static_cast<int>(in.points.size()) || !t.pixel.allFinite())
      return Error{"a tie observation names no pose or point, or its pixel is not finite"};
    poses_of[t.point].insert(t.pose);
  }
  if (Status s = CheckControlFields(in, stations); !s) return s;
  std::vector<char> tied(stations, 0);
  for (const auto& poses : poses_of) {
    std::set<int> of;
    for (int pose : poses) of.insert(in.poses[pose].station);
    if (of.size() > 1) return Error{"a tie point is seen from two stations"};
    if (poses.size() >= 2) tied[*of.begin()] = 1;
  }
  for (int s = 0; s < stations; ++s)
    if (!tied[s])
      return Error{(stations > 1 ? fmt::format("station {}: ", s + 1) : std::string()) +
                   "no point is seen from two stage poses: nothing ties the poses together"};
  return {};
}

// Each image observation's residual (pixels), squared.
std::vector<double> SquaredResiduals(const RigAdjustmentInput& in, const Unknowns& u) {
  const Placements placements(in);
  std::vector<double> squares;
  for (const RigTieObservation& t : in.observations) {
    double residual[2] = {1e30, 1e30};
    const double* x[] = {u.stage.data(),
                         u.levelling[in.poses[t.pose].station].data(),
                         u.encoder[t.pose].data(),
                         u.points[t.point].data(),
                         u.cameras.Intrinsics(t.side),
                         u.cameras.stereo.data()};
    TieCost(in.calibration, t, placements, 1.0).Evaluate(x, residual, nullptr);
    squares.push_back(residual[0] * residual[0] + residual[1] * residual[1]);
  }
  return squares;
}

// The sigma a mismatch is told by: each kind's variance component, but no more than its median
// squared residual says. Mismatched tie points that stay within k of the variance component
// inflate it and so keep themselves in (terraces seed 1: 0.28 px, where the median tie says 0.10
// px and the seams of the true calibration were 94 % within 2 sigma). The median of a normal
// error's squared residual is 0.455 sigma^2 for one coordinate and 1.386 sigma^2 for two; the
// residuals of an adjustment are smaller than the errors by their redundancy, which the ratio of
// that median to the mean square takes out. `squares` in pixels (SquaredResiduals).
ImageSigmas RejectionSigmas(const RigAdjustmentInput& in, const std::vector<char>& control,
                            const std::vector<double>& relative_sigma,
                            const std::vector<double>& squares, const std::vector<char>& rejected,
                            const ImageSigmas& variance_component) {
  std::array<std::vector<double>, 2> over_median;
  std::array<double, 2> mean_square{};
  for (size_t i = 0; i < squares.size(); ++i) {
    if (rejected[i]) continue;
    const RigTieObservation& t = in.observations[i];
    const int kind = control[t.point] ? 1 : 0;
    const double square = squares[i] / (relative_sigma[i] * relative_sigma[i]);
    over_median[kind].push_back(square / (t.along_epipolar_only ? 0.4549 : 1.3863));
    mean_square[kind] += square / (t.along_epipolar_only ? 1 : 2);
  }
  ImageSigmas sigma = variance_component;
  for (int kind : {0, 1}) {
    if (over_median[kind].empty()) continue;
    const double ratio = MedianInPlace(&over_median[kind]) /
                         (mean_square[kind] / static_cast<double>(over_median[kind].size()));
    sigma.sigma[kind] *= std::sqrt(std::min(1.0, ratio));
  }
  return sigma;
}

// Marks the observations off by more than k sigma (a mismatched tie point), and every
// observation of a point that no longer ties two poses (its position would be free along a
// ray); true when the marks changed. `control`: in.ControlPoints(); `sigma`: RejectionSigmas.
bool Reject(const RigAdjustmentInput& in, const std::vector<char>& control,
            const std::vector<double>& relative_sigma, const std::vector<double>& squares,
            const ImageSigmas& sigma, std::vector<char>* rejected) {
  std::vector<char> marks(squares.size());
  std::vector<std::set<int>> poses_of(in.points.size());
  for (size_t i = 0; i < squares.size(); ++i) {
    const int point = in.observations[i].point;
    marks[i] =
        squares[i] > 2.0 * std::pow(kRejectionK * sigma.Of(control[point]) * relative_sigma[i], 2);
    if (!marks[i]) poses_of[in.observations[i].point].insert(in.observations[i].pose);
  }
  for (size_t i = 0; i < squares.size(); ++i)
    if (poses_of[in.observations[i].point].size() < 2) marks[i] = 1;
  const bool changed = marks != *rejected;
  *rejected = std::move(marks);
  return changed;
}

}  // namespace

Result<RigAdjustment> AdjustRig(const RigAdjustmentInput& in, const RigAdjustmentOptions& o) {
  std::string why;
  if (!o.Check(&why)) return Error{"rig adjustment: " + why};
  if (Status s = CheckInput(in); !s) return Error{"rig adjustment: " + s.error()};
  const std::vector<RigStation> stations = in.Stations();
  const int station_count = static_cast<int>(stations.size());
  // The prior, one list (LevellingParameter): the stage's, then each station's levelling.
  const StageVector stage_prior = StageVectorOf(in.calibration.stage);
  std::vector<double> prior(stage_prior.begin(), stage_prior.end());
  for (const RigStation& s : stations)
    prior.insert(prior.end(), {s.levelling_deg.x(), s.levelling_deg.y()});
  // The stage's own levelling slots are the stations' (held, unused); the pan zero is the
  // azimuth datum; a control field's pose turns its set-up as its levelling would.
  std::set<int> held = {0, 1, kPanZero};
  for (const RigControlField& field : in.control_fields)
    held.insert({LevellingParameter(field.station, 0), LevellingParameter(field.station, 1)});
  RigAdjustment r;
  Unknowns u(in.calibration.rig);
  // The images' sigmas are estimated as variance components, so that the sigmas weigh the
  // images against the encoders, the inclinometer and the survey by what the images show.
  ImageSigmas pixel_sigma{{o.pixel_sigma_px, o.pixel_sigma_px}};
  const std::vector<char> control = in.ControlPoints();
  const std::vector<double> relative_sigma = RelativeSigmas(in, control);
  u.stage = stage_prior;
  u.levelling.resize(stations.size());
  for (int i = kStageParameterCount; i < static_cast<int>(prior.size()); ++i)
    u.Parameter(i) = prior[i];
  u.encoder.assign(in.poses.size(), {0.0, 0.0});
  u.points = in.points;
  for (const RigControlField& field : in.control_fields)
    u.field_pose.push_back(FieldPoseOf(field.l_from_field));
  std::vector<char> rejected(in.observations.size(), 0);
  // Each round starts from the last one's solution, a newly held parameter from its prior.
  for (int weighing = 0, observability = 0;;) {
    for (int i : held) u.Parameter(i) = prior[i];
    ceres::Problem problem;
    const bool robust = weighing == 0 && observability == 0;
    if (Status s = BuildProblem(in, control, relative_sigma, o, robust, pixel_sigma, prior, held,
                                rejected, &u, &problem);
        !s)
      return Error{"rig adjustment: " + s.error()};
    const std::vector<char> problem_rejected = rejected;
    if (Status s = Solve(robust, &problem); !s) return Error{"rig adjustment: " + s.error()};
    const std::vector<double> squared = SquaredResiduals(in, u);
    const ImageSums sums = SumImageResiduals(in, control, relative_sigma, squared, rejected);
    const int kept = sums.kept[0] + sums.kept[1];
    const std::vector<int> free = FreeParameters(&u, held, &problem);
    const std::vector<int> camera_free =
        FreeCameraParameters(in.calibration, o.refine_cameras, &u, &problem);
    const std::optional<ImageSigmas> image_sigma =
        EstimateImageSigmas(sums, static_cast<int>(free.size() + camera_free.size()),
                            SurveyRedundancy(in, u, problem), pixel_sigma);
    if (!image_sigma) return Error{"rig adjustment: fewer observations than unknowns"};
    bool reweigh = false;
    for (int kind : {0, 1})
      reweigh |= std::abs(image_sigma->sigma[kind] / pixel_sigma.sigma[kind] - 1.0) > 0.05;
    const bool marks_changed = Reject(
        in, control, relative_sigma, squared,
        RejectionSigmas(in, control, relative_sigma, squared, rejected, *image_sigma), &rejected);
    if ((reweigh || marks_changed) && weighing++ < kMaxWeightRounds) {
      pixel_sigma = *image_sigma;
      continue;
    }
    r.observations = kept;
    r.rejected_observation = problem_rejected;
    r.encoder_sigma_deg = o.encoder_sigma_deg;
    for (size_t i = 0; i < in.observations.size(); ++i)
      r.observation_sigma_px.push_back(image_sigma->Of(control[in.observations[i].point]) *
                                       relative_sigma[i]);
    r.rejected = static_cast<int>(in.observations.size()) - kept;
    const std::optional<ParameterCovariances> covariance = ParameterCovariance(
        &u, free, camera_free,
        o.refine_cameras ? Eigen::MatrixXd() : RigCameraCovariance(in.calibration), &problem);
    if (!covariance) return Error{"rig adjustment: the covariance of the stage cannot be computed"};
    std::vector<std::string> reasons;
    const std::vector<int> named =
        Undetermined(covariance->stage, free, o, station_count, &reasons);
    if (!named.empty() && observability++ < kMaxObservabilityRounds) {
      held.insert(named.begin(), named.end());
      r.undetermined.insert(r.undetermined.end(), reasons.begin(), reasons.end());
      continue;
    }
    r.rms_px = std::sqrt((sums.pixel_squares[0] + sums.pixel_squares[1]) / (2.0 * kept));
    r.image_sigma_px = image_sigma->sigma[sums.kept[0] > 0 ? 0 : 1];
    // The data's and the held cameras' shares: the undetermined are told by the data alone.
    const Eigen::MatrixXd stage_covariance =
        covariance->stage + covariance->stage_from_held_cameras;
    const auto sigma_of = [&](int i) { return std::sqrt(std::max(0.0, stage_covariance(i, i))); };
    for (int s = 0; s < station_count; ++s) {
      const int x = LevellingParameter(s, 0);
      r.levelling_deg.emplace_back(u.Parameter(x), u.Parameter(x + 1));
      r.levelling_sigma_deg.emplace_back(sigma_of(x), sigma_of(x + 1));
    }
    StageVector stage = u.stage;
    const auto share_of = [&](int i) {
      return std::sqrt(std::max(0.0, covariance->stage_from_held_cameras(i, i)));
    };
    for (int i = 0; i < kStageParameterCount; ++i) {
      r.sigma[i] = sigma_of(i);
      r.sigma_from_held_cameras[i] = share_of(i);
    }
    for (int axis : {0, 1}) {
      stage[axis] = r.levelling_deg[0][axis];
      r.sigma[axis] = r.levelling_sigma_deg[0][axis];
      r.sigma_from_held_cameras[axis] = share_of(LevellingParameter(0, axis));
    }
    r.stage = StageKinematicsOf(stage, in.calibration.stage);
    r.points = u.points;
    r.control = ControlFits(in, u, squared, rejected, image_sigma->sigma[1]);
    r.cameras = RigCamerasOf(in.calibration, u.cameras,
                             o.refine_cameras ? covariance->cameras : Eigen::MatrixXd());
    return r;
  }
}

StageVector RigAdjustment::SigmaOfTheData() const {
  StageVector data{};
  for (int i = 0; i < kStageParameterCount; ++i)
    data[i] = std::sqrt(std::max(
        0.0, sigma[i] * sigma[i] - sigma_from_held_cameras[i] * sigma_from_held_cameras[i]));
  return data;
}

Calibration RigAdjustment::Adjusted(const Calibration& given) const {
  Calibration c = given;
  c.stage = stage;
  c.rig = cameras.rig;
  c.left_precision = cameras.left_precision;
  c.right_precision = cameras.right_precision;
  c.stereo_precision = cameras.stereo_precision;
  return c;
}

std::vector<RigStation> RigAdjustmentInput::Stations() const {
  if (!stations.empty()) return stations;
  RigStation one;
  one.levelling_deg = {calibration.stage.levelling_x_deg, calibration.stage.levelling_y_deg};
  return {one};
}

std::vector<char> RigAdjustmentInput::ControlPoints() const {
  std::vector<char> control(points.size(), 0);
  for (const RigControlField& field : control_fields)
    for (int point : field.points)
      if (point >= 0 && point < static_cast<int>(points.size())) control[point] = 1;
  return control;
}

Calibration RigAdjustmentInput::CalibrationOf(int station) const {
  Calibration c = calibration;
  const Eigen::Vector2d levelling = Stations()[station].levelling_deg;
  c.stage.levelling_x_deg = levelling.x();
  c.stage.levelling_y_deg = levelling.y();
  return c;
}

RigAdjustmentInput JoinStations(const std::vector<RigAdjustmentInput>& inputs) {
  RigAdjustmentInput joined;
  if (inputs.empty()) return joined;
  joined.calibration = inputs.front().calibration;
  for (const RigAdjustmentInput& in : inputs) {
    const int first_pose = static_cast<int>(joined.poses.size());
    const int first_point = static_cast<int>(joined.points.size());
    const int first_station = static_cast<int>(joined.stations.size());
    for (const RigStation& s : in.Stations()) joined.stations.push_back(s);
    for (RigPose pose : in.poses) {
      pose.station += first_station;
      joined.poses.push_back(pose);
    }
    for (RigTieObservation t : in.observations) {
      t.pose += first_pose;
      t.point += first_point;
      joined.observations.push_back(t);
    }
    joined.points.insert(joined.points.end(), in.points.begin(), in.points.end());
    for (RigControlField field : in.control_fields) {
      field.station += first_station;
      for (int& point : field.points) point += first_point;
      joined.control_fields.push_back(std::move(field));
    }
    // Kept aligned with the points: a station without covariances adds zeros.
    joined.point_covariance_m2.resize(first_point, Eigen::Matrix3d::Zero());
    joined.point_covariance_m2.insert(joined.point_covariance_m2.end(),
                                      in.point_covariance_m2.begin(), in.point_covariance_m2.end());
  }
  joined.point_covariance_m2.resize(joined.points.size(), Eigen::Matrix3d::Zero());
  return joined;
}

}  // namespace ts
