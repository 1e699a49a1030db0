#include "processing/calibration/rig_cameras.h"

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <limits>
#include <string>

#include "processing/geometry/rotation.h"

namespace ts {

namespace {

constexpr int kIntrinsicsCount = CameraIntrinsics::kNumParameters;

// Where calibration.yaml keeps each block's precision.
constexpr std::array<const char*, 3> kBlockField = {"cameras.left", "cameras.right", "stereo"};

// The cameras' free parameters observed jointly with their covariance: r = L^-1 (x - x0),
// C = L L^T, over the parameter blocks in the problem (`first`: each block's first index in
// the list; `free`: indices in the list, block by block).
class CameraPrior : public ceres::CostFunction {
 public:
  CameraPrior(RigCameraVector value, Eigen::MatrixXd whitening, std::vector<int> first,
              std::vector<int> free)
      : value_(value),
        whitening_(std::move(whitening)),
        first_(std::move(first)),
        free_(std::move(free)) {
    set_num_residuals(static_cast<int>(free_.size()));
    for (int f : first_)
      mutable_parameter_block_sizes()->push_back(kCameraBlockSize[CameraBlockOf(f)]);
  }

  bool Evaluate(double const* const* x, double* residual, double** jacobians) const override {
    const int n = static_cast<int>(free_.size());
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i)
      d[i] = x[BlockOf(free_[i])][free_[i] - First(free_[i])] - value_[free_[i]];
    Eigen::Map<Eigen::VectorXd>(residual, n) = whitening_ * d;
    if (!jacobians) return true;
    for (size_t b = 0; b < first_.size(); ++b) {
      if (!jacobians[b]) continue;
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> j(
          jacobians[b], n, parameter_block_sizes()[b]);
      j.setZero();
      for (int i = 0; i < n; ++i)
        if (BlockOf(free_[i]) == static_cast<int>(b))
          j.col(free_[i] - first_[b]) = whitening_.col(i);
    }
    return true;
  }

 private:
  int BlockOf(int parameter) const {
    for (size_t b = 0; b < first_.size(); ++b)
      if (first_[b] == First(parameter)) return static_cast<int>(b);
    return -1;
  }
  static int First(int parameter) { return kCameraBlockFirst[CameraBlockOf(parameter)]; }
  RigCameraVector value_;
  Eigen::MatrixXd whitening_;
  std::vector<int> first_, free_;
};

// A block's parameters with a variance (the free ones) and those without (held), as indices in
// the list (rig_cameras.h's) and in the block.
struct BlockPrecision {
  std::vector<int> free, held_in_block;
};

BlockPrecision BlockPrecisionOf(const Eigen::MatrixXd& prior, int b) {
  BlockPrecision p;
  for (int i = 0; i < kCameraBlockSize[b]; ++i) {
    const int k = kCameraBlockFirst[b] + i;
    if (prior(k, k) > 0.0)
      p.free.push_back(k);
    else
      p.held_in_block.push_back(i);
  }
  return p;
}

}  // namespace

Eigen::MatrixXd RigCameraCovariance(const Calibration& c) {
  if (c.stereo_precision.joint_covariance.rows() == kRigCameraParameterCount)
    return c.stereo_precision.joint_covariance;
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(kRigCameraParameterCount, kRigCameraParameterCount);
  p.block(kCameraBlockFirst[0], kCameraBlockFirst[0], kIntrinsicsCount, kIntrinsicsCount) =
      c.left_precision.covariance;
  p.block(kCameraBlockFirst[1], kCameraBlockFirst[1], kIntrinsicsCount, kIntrinsicsCount) =
      c.right_precision.covariance;
  p.block(kCameraBlockFirst[2], kCameraBlockFirst[2], kStereoParameterCount,
          kStereoParameterCount) = c.stereo_precision.covariance;
  return p;
}

RigCameraVector RigCameraVectorOf(const StereoRig& rig) {
  const RigCameraUnknowns u(rig);
  RigCameraVector v;
  std::copy(u.intrinsics[0].begin(), u.intrinsics[0].end(), v.begin() + kCameraBlockFirst[0]);
  std::copy(u.intrinsics[1].begin(), u.intrinsics[1].end(), v.begin() + kCameraBlockFirst[1]);
  std::copy(u.stereo.begin(), u.stereo.end(), v.begin() + kCameraBlockFirst[2]);
  return v;
}

std::string RigCameraParameterName(int parameter) {
  static constexpr std::array<const char*, kStereoParameterCount> kStereoNames = {
      "baseline_m", "right_relative_omega_deg", "right_relative_phi_deg",
      "right_relative_kappa_deg"};
  const int block = CameraBlockOf(parameter), k = parameter - kCameraBlockFirst[block];
  if (block == 2) return std::string("stereo.") + kStereoNames[k];
  return std::string(block == 0 ? "left." : "right.") + CameraIntrinsics::kParameterNames[k];
}

RigCameraVector RigCameraSigmas(const RigCameras& cameras) {
  RigCameraVector sigma{};
  if (!cameras.refined) return sigma;
  std::copy(cameras.left_precision.sigma.begin(), cameras.left_precision.sigma.end(),
            sigma.begin() + kCameraBlockFirst[0]);
  std::copy(cameras.right_precision.sigma.begin(), cameras.right_precision.sigma.end(),
            sigma.begin() + kCameraBlockFirst[1]);
  sigma[kCameraBlockFirst[2]] = cameras.stereo_precision.baseline_sigma_m;
  for (int k = 0; k < 3; ++k)
    sigma[kCameraBlockFirst[2] + 1 + k] = cameras.stereo_precision.relative_sigma_deg[k];
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
    if (!p.free.empty() &&
        Eigen::LLT<Eigen::MatrixXd>(prior(p.free, p.free)).info() != Eigen::Success)
      return Error{std::string(kBlockField[b]) +
                   ".covariance: not positive definite: the cameras cannot be refined"};
  }
  const std::vector<int> free = RefinedCameraParameters(calibration);
  if (Eigen::LLT<Eigen::MatrixXd>(prior(free, free)).info() != Eigen::Success)
    return Error{"stereo.joint_covariance: not positive definite: the cameras cannot be refined"};
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
  // One prior over the blocks in the problem: the calibration's covariance joins them (a
  // block the problem lacks is marginalised by leaving its rows out).
  std::vector<double*> present;
  std::vector<int> first, free;
  for (int b = 0; b < 3; ++b) {
    if (!problem->HasParameterBlock(blocks[b])) continue;
    const BlockPrecision p = BlockPrecisionOf(prior, b);
    if (p.free.empty()) {
      problem->SetParameterBlockConstant(blocks[b]);
      continue;
    }
    present.push_back(blocks[b]);
    first.push_back(kCameraBlockFirst[b]);
    free.insert(free.end(), p.free.begin(), p.free.end());
    if (!p.held_in_block.empty())
      problem->SetManifold(blocks[b],
                           new ceres::SubsetManifold(kCameraBlockSize[b], p.held_in_block));
  }
  if (present.empty()) return {};
  const int n = static_cast<int>(free.size());
  const Eigen::LLT<Eigen::MatrixXd> llt(prior(free, free));
  problem->AddResidualBlock(
      new CameraPrior(RigCameraVectorOf(calibration.rig),
                      llt.matrixL().solve(Eigen::MatrixXd::Identity(n, n)), first, free),
      nullptr, present);
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
    p.covariance = covariance.block(kCameraBlockFirst[side], kCameraBlockFirst[side],
                                    kIntrinsicsCount, kIntrinsicsCount);
    for (int i = 0; i < kIntrinsicsCount; ++i)
      p.sigma[i] = std::sqrt(std::max(0.0, p.covariance(i, i)));
  }
  StereoPrecision& s = r.stereo_precision;
  s.covariance = covariance.block(kCameraBlockFirst[2], kCameraBlockFirst[2], kStereoParameterCount,
                                  kStereoParameterCount);
  s.joint_covariance = covariance;
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
