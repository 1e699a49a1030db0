#include "station/board_flags.h"

#include "station/commands.h"
#include "station/option_flags.h"

namespace ts {

void AddBoardFlags(CLI::App* cmd, BoardFlags* flags) {
  flags->chessboard_flag =
      cmd->add_option("--chessboard", flags->chessboard_size,
                      "inner corners COLUMNSxROWS (default " + flags->chessboard_size + ")");
  AddDeclaredOption(cmd, "--square", flags->chessboard, "square");
  flags->circle_markers_flag =
      AddDeclaredOption(cmd, "--circle-markers", flags->chessboard, "circle_markers");
  flags->charuco_flag =
      cmd->add_option("--charuco", flags->charuco_size,
                      "a ChArUco board (5x5 markers) of SQUARESxSQUARES instead; partial views "
                      "count")
          ->excludes(flags->chessboard_flag)
          ->excludes(flags->circle_markers_flag);
  cmd->add_option("--marker", flags->marker, "with --charuco: a marker's side, of a square")
      ->capture_default_str();
}

CalibrationBoard ParseBoardFlags(const BoardFlags& flags) {
  CalibrationBoard board;
  board.chessboard = flags.chessboard;
  if (!ParseBoardSize(flags.chessboard_size, &board.chessboard))
    throw CommandError("--chessboard: expected COLUMNSxROWS of inner corners, e.g. 9x6, got '" +
                       flags.chessboard_size + "'");
  std::string why;
  if (!board.chessboard.Check(&why)) throw CommandError("--chessboard: " + why);
  if (flags.charuco_size.empty()) return board;
  CharucoOptions charuco;
  charuco.marker = flags.marker;
  if (!ParseCharucoSize(flags.charuco_size, &charuco))
    throw CommandError("--charuco: expected SQUARESxSQUARES, e.g. 12x9, got '" +
                       flags.charuco_size + "'");
  charuco.corners.square = board.chessboard.square;
  if (!charuco.Check(&why)) throw CommandError("--charuco: " + why);
  board.charuco = charuco;
  return board;
}

}  // namespace ts
