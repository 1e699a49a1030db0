#pragma once
// OpenCV's stereo chessboard sample (../shared/data/calibration/opencv_stereo_chessboard/):
// the pairs in which both images show the whole 9 x 6 board (unit squares), the placement the
// pair's number; and views as OpenCV's calibration functions take them.
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "processing/calibration/chessboard.h"
#include "processing/calibration/target_views.h"

namespace ts {

inline const std::string kSampleBoards = TS_SHARED_DATA_DIR "/calibration/opencv_stereo_chessboard";

inline void DetectSamplePairs(TargetViews* left, TargetViews* right) {
  const ChessboardOptions board;
  for (TargetViews* side : {left, right}) side->target = ChessboardCorners(board);
  for (int i = 1; i <= 14; ++i) {
    char l[32], r[32];
    std::snprintf(l, sizeof(l), "left%02d.jpg", i);
    std::snprintf(r, sizeof(r), "right%02d.jpg", i);
    if (!std::filesystem::exists(kSampleBoards + "/" + l)) continue;
    const cv::Mat left_grey = cv::imread(kSampleBoards + "/" + l, cv::IMREAD_GRAYSCALE);
    const cv::Mat right_grey = cv::imread(kSampleBoards + "/" + r, cv::IMREAD_GRAYSCALE);
    left->width_px = right->width_px = left_grey.cols;
    left->height_px = right->height_px = left_grey.rows;
    auto lc = DetectChessboard(left_grey, board), rc = DetectChessboard(right_grey, board);
    if (!lc || !rc) continue;
    left->AddFullView(l, i, lc->pixels);
    right->AddFullView(r, i, rc->pixels);
  }
}

// Object and image points per view, as cv::calibrateCamera and cv::stereoCalibrate take them.
struct OpenCvCorners {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
};

inline OpenCvCorners ToOpenCvCorners(const TargetViews& v) {
  OpenCvCorners c;
  for (const TargetView& view : v.views) {
    c.object.emplace_back();
    c.image.emplace_back();
    for (size_t i = 0; i < view.ids.size(); ++i) {
      const Eigen::Vector3d& t = v.target[view.ids[i]];
      c.object.back().emplace_back(t.x(), t.y(), t.z());
      c.image.back().emplace_back(view.pixels[i].x(), view.pixels[i].y());
    }
  }
  return c;
}

}  // namespace ts
