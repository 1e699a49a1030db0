#pragma once
// The flags that name a printed calibration board, shared by `calibrate` (boards in files) and
// `capture --calibration` (boards checked as each pair arrives).
#include <CLI/CLI.hpp>
#include <string>

#include "processing/calibration/calibration_board.h"

namespace ts {

struct BoardFlags {
  std::string chessboard_size = "9x6";  // inner corners
  std::string charuco_size;             // a ChArUco board instead: SQUARESxSQUARES
  ChessboardOptions chessboard;         // its square
  double marker = CharucoOptions{}.marker;
  CLI::Option* chessboard_flag = nullptr;
  CLI::Option* charuco_flag = nullptr;
  CLI::Option* circle_markers_flag = nullptr;
};

// --chessboard, --square, --circle-markers, --charuco, --marker.
void AddBoardFlags(CLI::App* cmd, BoardFlags* flags);
// The board the flags name; a CommandError naming the flag when they do not.
CalibrationBoard ParseBoardFlags(const BoardFlags& flags);

}  // namespace ts
