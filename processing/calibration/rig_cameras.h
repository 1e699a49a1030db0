#pragma once
// The cameras in the rig adjustment (rig_adjustment.h): held by default; refined when the user
// asks (issue 21). Refined, each camera's interior orientation and the stereo pair's relative
// orientation are unknowns of the adjustment, observed by the calibration that gave them
// (calibrate camera / stereo) with the covariance it reported (RigCameraCovariance: joint where
// calibrate stereo kept it), and what the panoramas and a control field show of the cameras
// refines them in turn. Held, their calibration's covariance is carried into the stage's sigmas
// without the data refining them. A parameter that calibration fixed (no variance) stays fixed.
#include <ceres/jet.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <mutex>
#include <string>
#include <vector>

#include "core/result.h"
#include "processing/geometry/calibration.h"

namespace ceres {
class Problem;
}

namespace ts {

// The stereo pair as the adjustment varies it, StereoPrecision's parameters: the baseline (m)
// and left_from_right as omega-phi-kappa (deg). S_from_left stays: a turn of the baseline in
// the left camera turns both cameras in S together, which the rig's mounting rotation takes
// up (its lever, half the baseline, moves them by hundredths of a millimetre).
inline constexpr int kStereoParameterCount = 4;
using StereoVector = std::array<double, kStereoParameterCount>;
StereoVector StereoVectorOf(const StereoRig& rig);

using IntrinsicsVector = std::array<double, CameraIntrinsics::kNumParameters>;

// The cameras' parameters as one list: the left camera's (kParameterNames order), the right
// camera's, then the stereo pair's.
inline constexpr int kRigCameraParameterCount =
    2 * CameraIntrinsics::kNumParameters + kStereoParameterCount;
using RigCameraVector = std::array<double, kRigCameraParameterCount>;
RigCameraVector RigCameraVectorOf(const StereoRig& rig);
// "left.c", "right.k1", "stereo.baseline_m", ...
std::string RigCameraParameterName(int parameter);
// The block (left, right, stereo: RigCameraUnknowns::Blocks) that holds a parameter of the list.
inline int CameraBlockOf(int parameter) {
  return std::min(2, parameter / CameraIntrinsics::kNumParameters);
}
// Each block's first index in the list, and its size.
inline constexpr std::array<int, 3> kCameraBlockFirst = {0, CameraIntrinsics::kNumParameters,
                                                         2 * CameraIntrinsics::kNumParameters};
inline constexpr std::array<int, 3> kCameraBlockSize = {
    CameraIntrinsics::kNumParameters, CameraIntrinsics::kNumParameters, kStereoParameterCount};

struct RigCameraUnknowns {
  std::array<IntrinsicsVector, 2> intrinsics{};  // left, right
  StereoVector stereo{};
  explicit RigCameraUnknowns(const StereoRig& rig);
  double* Intrinsics(Side side) { return intrinsics[side == Side::kLeft ? 0 : 1].data(); }
  const double* Intrinsics(Side side) const {
    return intrinsics[side == Side::kLeft ? 0 : 1].data();
  }
  // The three blocks in the list's order.
  std::array<double*, 3> Blocks() {
    return {intrinsics[0].data(), intrinsics[1].data(), stereo.data()};
  }
  // `start` with these parameters.
  StereoRig Rig(const StereoRig& start) const;
};

// The cameras the adjustment leaves: the input's when held; when refined, adjusted, with
// their precision a posteriori.
struct RigCameras {
  bool refined = false;
  StereoRig rig;
  CameraPrecision left_precision, right_precision;
  StereoPrecision stereo_precision;
};

// The calibration's covariance of the list: the joint one calibrate stereo keeps, or without it
// block-diagonal; zero where it states no precision.
Eigen::MatrixXd RigCameraCovariance(const Calibration& calibration);

// The parameters of the list that are refined: those with a variance in `calibration`.
std::vector<int> RefinedCameraParameters(const Calibration& calibration);

// The cameras' precision can weigh them: known, its covariance positive definite; the error
// names the calibration file's field.
Status CheckCamerasRefinable(const Calibration& calibration);

// Held: the blocks constant. Refined: the blocks in the problem observed together by their
// calibration (one prior, RigCameraCovariance); an error when the calibration carries no
// precision (design values) or its covariance is not positive definite.
Status AddCameraPriors(const Calibration& calibration, bool refine, RigCameraUnknowns* u,
                       ceres::Problem* problem);

// Each parameter's sigma from the cameras' precision (0: held or unknown).
RigCameraVector RigCameraSigmas(const RigCameras& cameras);

// `covariance`: a posteriori, of the list (zero rows for held parameters); empty when the
// cameras were held.
RigCameras RigCamerasOf(const Calibration& calibration, const RigCameraUnknowns& u,
                        const Eigen::MatrixXd& covariance);

// A camera's place in S for a stereo vector, as jets of its four parameters. The same for every
// observation of the camera: computed once per set of values (residuals may be evaluated on
// several threads, hence the lock).
using StereoJet = ceres::Jet<double, kStereoParameterCount>;
class CameraInRig {
 public:
  CameraInRig(Side side, const Eigen::Matrix3d& s_from_left);
  // S_from_camera and the camera's centre in S.
  void Get(const double* stereo, Eigen::Matrix<StereoJet, 3, 3>* s_from_camera,
           Eigen::Matrix<StereoJet, 3, 1>* centre);

 private:
  const Side side_;
  const Eigen::Matrix3d s_from_left_;
  std::mutex mutex_;
  StereoVector key_;
  Eigen::Matrix<StereoJet, 3, 3> rotation_;
  Eigen::Matrix<StereoJet, 3, 1> centre_;
};

}  // namespace ts
