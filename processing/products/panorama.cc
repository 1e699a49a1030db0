#include "processing/products/panorama.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "processing/geometry/camera_model.h"

namespace ts {

cv::Mat RenderPanorama(const Calibration& cal, const std::vector<StereoPairImages>& pairs,
                       const PanoramaOptions& o) {
  const int cols = static_cast<int>(std::lround(360.0 / o.deg_per_px));
  const int rows =
      static_cast<int>(std::lround((o.max_elevation_deg - o.min_elevation_deg) / o.deg_per_px));
  cv::Mat pano(rows, cols, CV_8UC1, cv::Scalar(0));
  if (pairs.empty()) return pano;
  const CameraModel camera(cal.rig.left);
  std::vector<Eigen::Isometry3d> camera_from_l;
  std::vector<Eigen::Vector3d> axis_l;
  std::vector<cv::Mat> images;
  for (const StereoPairImages& p : pairs) {
    const Eigen::Isometry3d l_from_camera = cal.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg);
    camera_from_l.push_back(l_from_camera.inverse());
    axis_l.push_back(l_from_camera.linear().col(2));
    cv::Mat eight = p.left;
    if (p.left.depth() == CV_16U) p.left.convertTo(eight, CV_8U, 1.0 / 256.0);
    images.push_back(eight);
  }
  cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      const double el = (o.max_elevation_deg - (r + 0.5) * o.deg_per_px) * M_PI / 180.0;
      for (int c = 0; c < cols; ++c) {
        const double az = (c + 0.5) * o.deg_per_px * M_PI / 180.0;
        // Pan is clockwise seen from above, from +Y towards +X.
        const Eigen::Vector3d d(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el),
                                std::sin(el));
        size_t best = 0;
        for (size_t i = 1; i < axis_l.size(); ++i)
          if (axis_l[i].dot(d) > axis_l[best].dot(d)) best = i;
        // A far point along d (the baseline's parallax is negligible at 1 km).
        const Eigen::Vector3d in_camera = camera_from_l[best] * (1000.0 * d);
        Eigen::Vector2d px;
        if (!camera.Project(in_camera, &px) || !camera.InImage(px)) continue;
        const cv::Mat& img = images[best];
        const int x = std::clamp(static_cast<int>(std::lround(px.x())), 0, img.cols - 1);
        const int y = std::clamp(static_cast<int>(std::lround(px.y())), 0, img.rows - 1);
        pano.at<uint8_t>(r, c) = img.at<uint8_t>(y, x);
      }
    }
  });
  // Only the band of elevations some image saw.
  int top = 0, bottom = rows;
  while (top < bottom && cv::countNonZero(pano.row(top)) == 0) ++top;
  while (bottom > top && cv::countNonZero(pano.row(bottom - 1)) == 0) --bottom;
  return top < bottom ? pano.rowRange(top, bottom).clone() : pano;
}

}  // namespace ts
