#pragma once
// Epipolar rectification of a stereo pair with the project's camera model (lens distortion
// included), so that conjugate points lie on the same row and matching is a 1D search.
//
// Both cameras are turned to the orientation of the rig frame S's nominal camera (x along the
// baseline from left to right, z along Y_S, y down), which S defines already. Both share one
// distortion-free pinhole (focal f, principal point (cx, cy)), so a point at depth Z (along
// rectified z) has disparity d = x_l - x_r = f B / Z. The maps give, for every rectified pixel, the
// measured pixel of the original image (CameraModel::Project with distortion), for cv::remap.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "processing/geometry/stereo_rig.h"

namespace ts {

struct Rectification {
  double focal_px = 0.0;
  Eigen::Vector2d principal_point_px{0, 0};
  int width_px = 0, height_px = 0;
  double baseline_m = 0.0;
  Eigen::Matrix3d left_from_rect = Eigen::Matrix3d::Identity();  // rotations
  Eigen::Matrix3d right_from_rect = Eigen::Matrix3d::Identity();
  cv::Mat left_map_x, left_map_y, right_map_x, right_map_y;  // CV_32FC1

  // Rectified pixel of a point given in the left camera frame (and its right counterpart).
  Eigen::Vector2d LeftPixel(const Eigen::Vector3d& point_left) const;
  Eigen::Vector2d RightPixel(const Eigen::Vector3d& point_left) const;
  // Depth along the rectified viewing axis from a disparity (px).
  double DepthFromDisparity(double disparity_px) const {
    return focal_px * baseline_m / disparity_px;
  }
  // The whole-pixel disparities to search for depths from min_depth_m to max_depth_m.
  int MinDisparityPx(double max_depth_m) const;
  int MaxDisparityPx(double min_depth_m) const;
};

// Rectified images keep the original size; the focal length is the smaller of the two
// cameras' so that the rectified view does not crop far beyond the originals.
Rectification Rectify(const StereoRig& rig);

// Both images through their maps (bilinear), CV_32FC1 out.
void RectifyPair(const Rectification& r, const cv::Mat& left, const cv::Mat& right,
                 cv::Mat* left_rect, cv::Mat* right_rect);

}  // namespace ts
