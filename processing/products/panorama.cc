#include "processing/products/panorama.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "processing/geometry/camera_model.h"

namespace ts {

bool PanoramaOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!(min_elevation_deg < max_elevation_deg))
    err = "min_elevation_deg must be below max_elevation_deg";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

PanoramaBuilder::PanoramaBuilder(const Calibration& calibration, const PanoramaOptions& o)
    : calibration_(calibration), options_(o) {
  const int cols = static_cast<int>(std::lround(360.0 / o.deg_per_px));
  const int rows =
      static_cast<int>(std::lround((o.max_elevation_deg - o.min_elevation_deg) / o.deg_per_px));
  pano_ = cv::Mat(rows, cols, CV_8UC1, cv::Scalar(0));
  best_dot_ = cv::Mat(rows, cols, CV_64FC1, cv::Scalar(-2.0));  // below any cosine
}

void PanoramaBuilder::Add(const std::vector<StereoPairImages>& pairs) {
  const PanoramaOptions& o = options_;
  const CameraModel camera(calibration_.rig.left);
  std::vector<Eigen::Isometry3d> camera_from_l;
  std::vector<Eigen::Vector3d> axis_l;
  std::vector<cv::Mat> images;
  for (const StereoPairImages& p : pairs) {
    const Eigen::Isometry3d l_from_camera =
        calibration_.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg);
    camera_from_l.push_back(l_from_camera.inverse());
    axis_l.push_back(l_from_camera.linear().col(2));
    cv::Mat eight = p.left;
    if (p.left.depth() == CV_16U) p.left.convertTo(eight, CV_8U, 1.0 / 256.0);
    images.push_back(eight);
  }
  cv::parallel_for_(cv::Range(0, pano_.rows), [&](const cv::Range& range) {
    for (int r = range.start; r < range.end; ++r) {
      const double el = (o.max_elevation_deg - (r + 0.5) * o.deg_per_px) * M_PI / 180.0;
      for (int c = 0; c < pano_.cols; ++c) {
        const double az = (c + 0.5) * o.deg_per_px * M_PI / 180.0;
        // Pan is clockwise seen from above, from +Y towards +X.
        const Eigen::Vector3d d(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el),
                                std::sin(el));
        int best = -1;
        double best_dot = best_dot_.at<double>(r, c);
        for (size_t i = 0; i < axis_l.size(); ++i)
          if (axis_l[i].dot(d) > best_dot) best = static_cast<int>(i), best_dot = axis_l[i].dot(d);
        if (best < 0) continue;  // an image added before is closer
        best_dot_.at<double>(r, c) = best_dot;
        uint8_t& value = pano_.at<uint8_t>(r, c);
        value = 0;  // the closest image decides, seen or not
        // A far point along d (the baseline's parallax is negligible at 1 km).
        Eigen::Vector2d px;
        if (!camera.Project(camera_from_l[best] * (1000.0 * d), &px) || !camera.InImage(px))
          continue;
        const cv::Mat& img = images[best];
        const int x = std::clamp(static_cast<int>(std::lround(px.x())), 0, img.cols - 1);
        const int y = std::clamp(static_cast<int>(std::lround(px.y())), 0, img.rows - 1);
        value = img.at<uint8_t>(y, x);
      }
    }
  });
}

double LargestViewTurnDeg(const Calibration& from, const Calibration& to,
                          const std::vector<StereoPairImages>& pairs) {
  double largest = 0.0;
  for (const StereoPairImages& p : pairs) {
    const Eigen::Matrix3d turn =
        to.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg).linear() *
        from.LFromCamera(Side::kLeft, p.pan_deg, p.tilt_deg).linear().transpose();
    largest = std::max(largest, Eigen::AngleAxisd(turn).angle() * 180.0 / M_PI);
  }
  return largest;
}

cv::Mat PanoramaBuilder::Image() const {
  // Only the band of elevations some image saw.
  int top = 0, bottom = pano_.rows;
  while (top < bottom && cv::countNonZero(pano_.row(top)) == 0) ++top;
  while (bottom > top && cv::countNonZero(pano_.row(bottom - 1)) == 0) --bottom;
  return top < bottom ? pano_.rowRange(top, bottom).clone() : pano_.clone();
}

cv::Mat RenderPanorama(const Calibration& cal, const std::vector<StereoPairImages>& pairs,
                       const PanoramaOptions& o) {
  PanoramaBuilder builder(cal, o);
  builder.Add(pairs);
  return builder.Image();
}

}  // namespace ts
