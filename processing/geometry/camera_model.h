#pragma once
// The one camera model of topostation: collinearity with principal distance, principal point,
// Brown distortion (K1 K2 K3 P1 P2) and affinity/shear, as seed 000 eqs. 2-6 (Smit, Ruther,
// Siebrits). The renderer, calibration, matching and intersection all use this file.
//
// Frames and units
//   Camera frame C: x right (image columns), y down (image rows), z forward (viewing axis).
//   Pixel coordinates: origin at the centre of the top-left pixel, x right, y down, in px.
//
// The correction form of seed 000: for a measured pixel m with reduced coordinates
//   r = m - pp   (pp = principal point),
// the ideal (distortion-free) reduced coordinates are  i = r + d(r), and collinearity says
//   i = c * (X/Z, Y/Z)    (c = principal distance, X Y Z = point in C).
// d is seed 000 eqs. 4-5 evaluated on coordinates normalised by c, n = r / c, so that all
// coefficients are dimensionless (K1 here = K1_seed * c^2, P1 = P1_seed * c):
//   d_x / c = nx*Sx + ny*a + nx*(K1 r2 + K2 r2^2 + K3 r2^3) + P1 (r2 + 2 nx^2) + 2 P2 nx ny
//   d_y / c = nx*a          + ny*(K1 r2 + K2 r2^2 + K3 r2^3) + 2 P1 nx ny + P2 (r2 + 2 ny^2)
// with r2 = nx^2 + ny^2. Back-projection is therefore explicit; projection solves r + d(r) = i
// by Newton's method (a few iterations for any real lens).
#include <Eigen/Core>
#include <array>
#include <string>

namespace ts {

// Interior orientation of one camera. A plain struct; Check() says what is wrong.
struct CameraIntrinsics {
  int width_px = 0;                     // image width
  int height_px = 0;                    // image height
  double pixel_size_um = 0.0;           // physical pixel pitch; 0 = unknown (reporting only)
  double principal_distance_px = 0.0;   // c, > 0
  double principal_point_x_px = 0.0;    // xp
  double principal_point_y_px = 0.0;    // yp
  double k1 = 0.0, k2 = 0.0, k3 = 0.0;  // radial distortion, dimensionless (see above)
  double p1 = 0.0, p2 = 0.0;            // decentring distortion, dimensionless
  double scale_x = 0.0;                 // affinity S_x, dimensionless (0 = square pixels)
  double shear = 0.0;                   // shear a, dimensionless

  bool Check(std::string* why) const;

  // Parameter vector in the order of kParameterNames, for calibration and Jacobians.
  static constexpr int kNumParameters = 10;
  static constexpr std::array<const char*, kNumParameters> kParameterNames = {
      "c", "xp", "yp", "k1", "k2", "k3", "p1", "p2", "scale_x", "shear"};
  std::array<double, kNumParameters> ToParameters() const;
  static CameraIntrinsics FromParameters(const std::array<double, kNumParameters>& p, int width_px,
                                         int height_px, double pixel_size_um);
};

// d(r) of the header comment for reduced coordinates (rx, ry); templated so that Ceres
// can differentiate it automatically. p follows CameraIntrinsics::kParameterNames.
template <typename T>
void DistortionCorrection(const T* p, const T& rx, const T& ry, T* dx, T* dy) {
  const T& c = p[0];
  const T nx = rx / c, ny = ry / c;
  const T r2 = nx * nx + ny * ny;
  const T radial = r2 * (p[3] + r2 * (p[4] + r2 * p[5]));
  *dx = c * (nx * p[8] + ny * p[9] + nx * radial + p[6] * (r2 + T(2) * nx * nx) +
             T(2) * p[7] * nx * ny);
  *dy = c * (nx * p[9] + ny * radial + T(2) * p[6] * nx * ny + p[7] * (r2 + T(2) * ny * ny));
}

class CameraModel {
 public:
  using Jacobian2x3 = Eigen::Matrix<double, 2, 3>;
  using JacobianIntrinsics = Eigen::Matrix<double, 2, CameraIntrinsics::kNumParameters>;

  explicit CameraModel(const CameraIntrinsics& intrinsics);
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }

  // Pixel of a point in the camera frame. False if the point is not in front of the camera
  // (z <= 0) or the distortion cannot be inverted there. Optional analytic Jacobians of the
  // pixel with respect to the point and to the intrinsic parameters.
  bool Project(const Eigen::Vector3d& point_c, Eigen::Vector2d* pixel,
               Jacobian2x3* d_pixel_d_point = nullptr,
               JacobianIntrinsics* d_pixel_d_intrinsics = nullptr) const;

  // Unit viewing ray in the camera frame through a measured pixel (explicit, no iteration).
  Eigen::Vector3d RayFromPixel(const Eigen::Vector2d& pixel) const;

  // Measured pixel -> ideal (distortion-free) pixel, with optional Jacobian d ideal / d pixel.
  Eigen::Vector2d Undistort(const Eigen::Vector2d& pixel,
                            Eigen::Matrix2d* d_ideal_d_pixel = nullptr) const;
  // Ideal pixel -> measured pixel (Newton). False if it does not converge.
  bool Distort(const Eigen::Vector2d& ideal_pixel, Eigen::Vector2d* pixel) const;

  bool InImage(const Eigen::Vector2d& pixel) const;

 private:
  // Reduced measured r -> ideal reduced i = r + d(r), with J = di/dr.
  Eigen::Vector2d IdealReduced(const Eigen::Vector2d& r, Eigen::Matrix2d* jacobian) const;
  bool SolveReduced(const Eigen::Vector2d& ideal, Eigen::Vector2d* r,
                    Eigen::Matrix2d* jacobian) const;

  CameraIntrinsics intrinsics_;
  std::array<double, CameraIntrinsics::kNumParameters> params_;
  Eigen::Vector2d principal_point_;
};

}  // namespace ts
