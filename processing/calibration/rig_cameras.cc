#include "processing/calibration/rig_cameras.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <limits>
#include <string>

#include "processing/geometry/rotation.h"

namespace ts {

namespace {

constexpr int kIntrinsicsCount = CameraIntrinsics::kNumParameters;

// First index of each block in the list, and its size.
constexpr std::array<int, 3> kBlockFirst = {0, kIntrinsicsCount, 2 * kIntrinsicsCount};
constexpr std::array<int, 3> kBlockSize = {kIntrinsicsCount, kIntrinsicsCount,
                                           kStereoParameterCount};
// Where calibration.yaml keeps each block's precision.
constexpr std::array<const char*, 3> kBlockField = {"cameras.left", "cameras.right", "stereo"};

// A block's free parameters observed with their covariance: r = L^-1 (x - x0), C = L L^T.
class BlockPrior : public ceres::CostFunction {
 public:
  BlockPrior(std::vector<double> value, Eigen::MatrixXd whitening, std::vector<int> free, int size)
      : value_(std::move(value)), whitening_(std::move(whitening)), free_(std::move(free)) {
    set_num_residuals(static_cast<int>(free_.size()));
    mutable_parameter_block_sizes()->push_back(size);
  }

  bool Evaluate(double const* const* x, double* residual, double** jacobians) const override {
    const int n = static_cast<int>(free_.size());
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) d[i] = x[0][free_[i]] - value_[free_[i]];
    Eigen::Map<Eigen::VectorXd>(residual, n) = whitening_ * d;
    if (jacobians && jacobians[0]) {
      const int size = parameter_block_sizes()[0];
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> j(
          jacobians[0], n, size);
      j.setZero();
      for (int i = 0; i < n; ++i) j.col(free_[i]) = whitening_.col(i);
    }
    return true;
  }

 private:
  std::vector<double> value_;
  Eigen::MatrixXd whitening_;
  std::vector<int> free_;
};

// A block's parameters with a variance (the free ones) and those without (held), and the
// Cholesky factor of the free ones' covariance.
struct BlockPrecision {
  std::vector<int> free, held;
  Eigen::LLT<Eigen::MatrixXd> llt;
};

BlockPrecision BlockPrecisionOf(const Eigen::MatrixXd& prior, int b) {
  BlockPrecision p;
  for (int i = 0; i < kBlockSize[b]; ++i)
    (prior(kBlockFirst[b] + i, kBlockFirst[b] + i) > 0.0 ? p.free : p.held).push_back(i);
  const int n = static_cast<int>(p.free.size());
  Eigen::MatrixXd covariance(n, n);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k)
      covariance(i, k) = prior(kBlockFirst[b] + p.free[i], kBlockFirst[b] + p.free[k]);
  p.llt.compute(covariance);
  return p;
}

}  // namespace

Eigen::MatrixXd RigCameraCovariance(const Calibration& c) {
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(kRigCameraParameterCount, kRigCameraParameterCount);
  p.block(kBlockFirst[0], kBlockFirst[0], kIntrinsicsCount, kIntrinsicsCount) =
      c.left_precision.covariance;
  p.block(kBlockFirst[1], kBlockFirst[1], kIntrinsicsCount, kIntrinsicsCount) =
      c.right_precision.covariance;
  p.block(kBlockFirst[2], kBlockFirst[2], kStereoParameterCount, kStereoParameterCount) =
      c.stereo_precision.covariance;
  return p;
}

RigCameraVector RigCameraVectorOf(const StereoRig& rig) {
  const RigCameraUnknowns u(rig);
  RigCameraVector v;
  std::copy(u.intrinsics[0].begin(), u.intrinsics[0].end(), v.begin() + kBlockFirst[0]);
  std::copy(u.intrinsics[1].begin(), u.intrinsics[1].end(), v.begin() + kBlockFirst[1]);
  std::copy(u.stereo.begin(), u.stereo.end(), v.begin() + kBlockFirst[2]);
  return v;
}

std::string RigCameraParameterName(int parameter) {
  static constexpr std::array<const char*, kStereoParameterCount> kStereoNames = {
      "baseline_m", "right_relative_omega_deg", "right_relative_phi_deg",
      "right_relative_kappa_deg"};
  const int block = CameraBlockOf(parameter), k = parameter - kBlockFirst[block];
  if (block == 2) return std::string("stereo.") + kStereoNames[k];
  return std::string(block == 0 ? "left." : "right.") + CameraIntrinsics::kParameterNames[k];
}

RigCameraVector RigCameraSigmas(const RigCameras& cameras) {
  RigCameraVector sigma{};
  if (!cameras.refined) return sigma;
  std::copy(cameras.left_precision.sigma.begin(), cameras.left_precision.sigma.end(),
            sigma.begin() + kBlockFirst[0]);
  std::copy(cameras.right_precision.sigma.begin(), cameras.right_precision.sigma.end(),
            sigma.begin() + kBlockFirst[1]);
  sigma[kBlockFirst[2]] = cameras.stereo_precision.baseline_sigma_m;
  for (int k = 0; k < 3; ++k)
    sigma[kBlockFirst[2] + 1 + k] = cameras.stereo_precision.relative_sigma_deg[k];
  return sigma;
}

StereoVector StereoVectorOf(const StereoRig& rig) {
  const Eigen::Vector3d opk = OpkDegFromRotation(rig.left_from_right);
  return {rig.baseline_m, opk.x(), opk.y(), opk.z()};
}

RigCameraUnknowns::RigCameraUnknowns(const StereoRig& rig)
    : intrinsics{rig.left.ToParameters(), rig.right.ToParameters()}, stereo(StereoVectorOf(rig)) {}

StereoRig RigCameraUnknowns::Rig(const StereoRig& start) const {
  StereoRig rig = start;
  rig.left = CameraIntrinsics::FromParameters(intrinsics[0], start.left.width_px,
                                              start.left.height_px, start.left.pixel_size_um);
  rig.right = CameraIntrinsics::FromParameters(intrinsics[1], start.right.width_px,
                                               start.right.height_px, start.right.pixel_size_um);
  rig.baseline_m = stereo[0];
  rig.left_from_right = RotationFromOpkDeg(stereo[1], stereo[2], stereo[3]);
  return rig;
}

std::vector<int> RefinedCameraParameters(const Calibration& calibration) {
  const Eigen::MatrixXd prior = RigCameraCovariance(calibration);
  std::vector<int> refined;
  for (int i = 0; i < kRigCameraParameterCount; ++i)
    if (prior(i, i) > 0.0) refined.push_back(i);
  return refined;
}

Status CheckCamerasRefinable(const Calibration& calibration) {
  const std::array<bool, 3> known = {calibration.left_precision.known,
                                     calibration.right_precision.known,
                                     calibration.stereo_precision.known};
  const Eigen::MatrixXd prior = RigCameraCovariance(calibration);
  for (int b = 0; b < 3; ++b) {
    if (!known[b])
      return Error{std::string(kBlockField[b]) +
                   ": no precision (sigma, covariance) to weigh it by, as calibrate camera and "
                   "calibrate stereo write it: the cameras cannot be refined (design values?)"};
    const BlockPrecision p = BlockPrecisionOf(prior, b);
    if (!p.free.empty() && p.llt.info() != Eigen::Success)
      return Error{std::string(kBlockField[b]) +
                   ".covariance: not positive definite: the cameras cannot be refined"};
  }
  return {};
}

Status AddCameraPriors(const Calibration& calibration, bool refine, RigCameraUnknowns* u,
                       ceres::Problem* problem) {
  const std::array<double*, 3> blocks = u->Blocks();
  if (!refine) {
    for (double* block : blocks)
      if (problem->HasParameterBlock(block)) problem->SetParameterBlockConstant(block);
    return {};
  }
  if (Status s = CheckCamerasRefinable(calibration); !s) return s;
  const Eigen::MatrixXd prior = RigCameraCovariance(calibration);
  RigCameraUnknowns start(calibration.rig);
  const std::array<double*, 3> values = start.Blocks();
  for (int b = 0; b < 3; ++b) {
    if (!problem->HasParameterBlock(blocks[b])) continue;
    const BlockPrecision p = BlockPrecisionOf(prior, b);
    const std::vector<int>&free = p.free, &held = p.held;
    if (free.empty()) {
      problem->SetParameterBlockConstant(blocks[b]);
      continue;
    }
    const int n = static_cast<int>(free.size());
    const Eigen::MatrixXd whitening = p.llt.matrixL().solve(Eigen::MatrixXd::Identity(n, n));
    problem->AddResidualBlock(
        new BlockPrior(std::vector<double>(values[b], values[b] + kBlockSize[b]), whitening, free,
                       kBlockSize[b]),
        nullptr, blocks[b]);
    if (!held.empty())
      problem->SetManifold(blocks[b], new ceres::SubsetManifold(kBlockSize[b], held));
  }
  return {};
}

RigCameras RigCamerasOf(const Calibration& calibration, const RigCameraUnknowns& u,
                        const Eigen::MatrixXd& covariance) {
  RigCameras r;
  r.rig = calibration.rig;
  r.left_precision = calibration.left_precision;
  r.right_precision = calibration.right_precision;
  r.stereo_precision = calibration.stereo_precision;
  if (covariance.size() == 0) return r;
  r.refined = true;
  r.rig = u.Rig(calibration.rig);
  for (int side = 0; side < 2; ++side) {
    CameraPrecision& p = side == 0 ? r.left_precision : r.right_precision;
    p.covariance =
        covariance.block(kBlockFirst[side], kBlockFirst[side], kIntrinsicsCount, kIntrinsicsCount);
    for (int i = 0; i < kIntrinsicsCount; ++i)
      p.sigma[i] = std::sqrt(std::max(0.0, p.covariance(i, i)));
  }
  StereoPrecision& s = r.stereo_precision;
  s.covariance = covariance.block(kBlockFirst[2], kBlockFirst[2], kStereoParameterCount,
                                  kStereoParameterCount);
  s.baseline_sigma_m = std::sqrt(std::max(0.0, s.covariance(0, 0)));
  for (int k = 0; k < 3; ++k)
    s.relative_sigma_deg[k] = std::sqrt(std::max(0.0, s.covariance(1 + k, 1 + k)));
  return r;
}

CameraInRig::CameraInRig(Side side, const Eigen::Matrix3d& s_from_left)
    : side_(side), s_from_left_(s_from_left) {
  key_.fill(std::numeric_limits<double>::quiet_NaN());
}

void CameraInRig::Get(const double* stereo, Eigen::Matrix<StereoJet, 3, 3>* s_from_camera,
                      Eigen::Matrix<StereoJet, 3, 1>* centre) {
  StereoVector key;
  std::copy(stereo, stereo + kStereoParameterCount, key.begin());
  std::lock_guard lock(mutex_);
  if (key != key_) {
    const StereoJet half_baseline = 0.5 * StereoJet(key[0], 0);
    const StereoJet zero(0.0);
    rotation_ = s_from_left_.cast<StereoJet>();
    centre_ = {-half_baseline, zero, zero};
    if (side_ == Side::kRight) {
      rotation_ = rotation_ * RotationFromOpkDeg(StereoJet(key[1], 1), StereoJet(key[2], 2),
                                                 StereoJet(key[3], 3));
      centre_.x() = half_baseline;
    }
    key_ = key;
  }
  *s_from_camera = rotation_;
  *centre = centre_;
}

}  // namespace ts
