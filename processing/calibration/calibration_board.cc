#include "processing/calibration/calibration_board.h"

#include <fmt/format.h>

namespace ts {

std::vector<Eigen::Vector3d> CalibrationBoard::Corners() const {
  return ChessboardCorners(charuco ? charuco->corners : chessboard);
}

std::string CalibrationBoard::Describe() const {
  const ChessboardOptions& c = charuco ? charuco->corners : chessboard;
  return fmt::format("{}x{} {}", c.columns, c.rows,
                     charuco            ? "ChArUco board"
                     : c.circle_markers ? "chessboard with circle markers"
                                        : "chessboard");
}

std::optional<TargetView> DetectBoard(const cv::Mat& grey, const CalibrationBoard& board) {
  return board.charuco ? DetectCharuco(grey, *board.charuco)
                       : DetectChessboard(grey, board.chessboard);
}

}  // namespace ts
