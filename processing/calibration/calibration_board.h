#pragma once
// A printed calibration board, chessboard or ChArUco, and its detection in one image: what
// `calibrate` reads from files and `capture --calibration` checks as each pair arrives.
#include <optional>
#include <string>
#include <vector>

#include "processing/calibration/charuco.h"
#include "processing/calibration/chessboard.h"
#include "processing/calibration/target_views.h"

namespace ts {

struct CalibrationBoard {
  ChessboardOptions chessboard;  // a ChArUco board's inner corners and square too
  std::optional<CharucoOptions> charuco;

  // The inner corners in the board's frame (TargetViews::target).
  std::vector<Eigen::Vector3d> Corners() const;
  // "9x6 chessboard", "11x8 ChArUco board" (inner corners).
  std::string Describe() const;
};

// The board's corners in a grey image (CV_8UC1) with their ids: a plain chessboard's all or none,
// one with circle markers the part about its markers, a ChArUco board's any six or more; none
// when the board is not found.
std::optional<TargetView> DetectBoard(const cv::Mat& grey, const CalibrationBoard& board);

}  // namespace ts
