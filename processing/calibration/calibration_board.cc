#include "processing/calibration/calibration_board.h"

#include <fmt/format.h>

namespace ts {

std::vector<Eigen::Vector3d> CalibrationBoard::Corners() const {
  return ChessboardCorners(charuco ? charuco->corners : chessboard);
}

std::string CalibrationBoard::Describe() const {
  const ChessboardOptions& c = charuco ? charuco->corners : chessboard;
  return fmt::format("{}x{} {}", c.columns, c.rows, charuco ? "ChArUco board" : "chessboard");
}

std::optional<TargetView> DetectBoard(const cv::Mat& grey, const CalibrationBoard& board) {
  if (board.charuco) return DetectCharuco(grey, *board.charuco);
  const std::optional<std::vector<Eigen::Vector2d>> corners =
      DetectChessboard(grey, board.chessboard);
  if (!corners) return std::nullopt;
  TargetView view;
  view.pixels = *corners;
  for (size_t i = 0; i < corners->size(); ++i) view.ids.push_back(static_cast<int>(i));
  return view;
}

}  // namespace ts
