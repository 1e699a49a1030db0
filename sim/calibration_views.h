#pragma once
// Calibration views of the simulated rig's true (imperfect) cameras: a chessboard, or a ChArUco
// board, held at many poses and distances in front of the stereo pair, as a field team takes
// them. Each image is
// rendered exactly through the true camera model (every sample's ray from its measured pixel,
// camera_model.h, met with the board's plane), anti-aliased by supersampling, then exposed by
// the sensor model with its noise. Some placements run partly out of a frame, some are blurred
// (a hand that moved), some show no board: the calibration must skip and name them.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/options.h"
#include "core/result.h"
#include "processing/calibration/charuco.h"
#include "processing/calibration/chessboard.h"
#include "sim/sim_rig.h"

namespace ts::sim {

// The radiance of printed calibration targets (boards, a field's targets): black ink, white
// paper, and the grey wall behind them.
inline constexpr float kTargetBlack = 0.06f, kTargetWhite = 0.8f, kTargetBackground = 0.35f;

struct BoardSessionOptions {
  // A session that determines the rig: many placements of a board with many corners, tilted
  // strongly (the principal point comes from the tilts), near enough to fill much of the frame,
  // held at each part of each camera's frame in turn (PlanBoardSession).
  int placements = 40;
  int columns = 16;  // inner corners
  int rows = 11;
  double square_m = 0.07;
  double min_distance_m = 1.5;
  double max_distance_m = 3.0;
  double max_tilt_deg = 50.0;
  // A ChArUco board (charuco.h) of the same inner corners: its markers a share of a square.
  bool charuco = false;
  double marker = CharucoOptions{}.marker;
  // A chessboard with OpenCV's three circle markers (chessboard.h): partial views count too.
  bool circle_markers = false;
  // Of the placements, boards held running off the frame (a ChArUco board's corners there
  // still count, and a chessboard's with circle markers in view).
  double beyond_share = 0.125;
  double blurred_share = 0.1;  // of the placements, blurred by 1.5 px
  double empty_share = 0.05;   // of the placements, no board in view
  int supersampling = 4;       // per axis
  double exposure_us = 3000.0;
  template <class Self, class V>
  static void Declare(Self& self, V& v) {
    v("placements", self.placements, {"board placements (stereo pairs)", "", 1, 1000});
    v("columns", self.columns, {"inner corners along a row", "", 3, 50});
    v("rows", self.rows, {"inner corners along a column", "", 3, 50});
    v("square_m", self.square_m, {"side of a square", "m", 0.005, 1});
    v("min_distance_m", self.min_distance_m, {"nearest board", "m", 0.3, 100});
    v("max_distance_m", self.max_distance_m, {"farthest board", "m", 0.3, 100});
    v("max_tilt_deg", self.max_tilt_deg, {"board tilt from facing the rig, at most", "deg", 0, 70});
    v("charuco", self.charuco, {"a ChArUco board instead of a chessboard"});
    v("marker", self.marker, {"ChArUco marker side, of a square", "", 0.1, 0.99});
    v("circle_markers", self.circle_markers, {"a chessboard with three circle markers"});
    v("beyond_share", self.beyond_share, {"share of placements running off the frame", "", 0, 1});
    v("blurred_share", self.blurred_share, {"share of placements blurred", "", 0, 1});
    v("empty_share", self.empty_share, {"share of placements without a board", "", 0, 1});
    v("supersampling", self.supersampling, {"samples per pixel per axis", "", 1, 16});
    v("exposure_us", self.exposure_us, {"exposure time", "us", 10, 1e6});
  }
  bool Check(std::string* why) const;
  ChessboardOptions Board() const { return {columns, rows, square_m, circle_markers}; }
  CharucoOptions Charuco() const { return {{columns, rows, square_m}, marker}; }
};

struct BoardPlacement {
  std::string name;  // "03"
  Eigen::Isometry3d left_from_board = Eigen::Isometry3d::Identity();
  bool board = true;  // false: a view without a board
  bool blurred = false;
  cv::Mat left, right;  // Mono8
};

// A ChArUco session: a part of the board counts, so the team holds it off the frame's edges on
// purpose (the distortion is measured where it is largest) and nearer than a chessboard that
// must be seen whole, 1-2.5 m, where the tilted boards fill the frame with the perspective that
// fixes the principal point (at 1.5-3 m the principal point is found to 0.33 px, the relative
// angles to 0.011 deg, over ten seeds; at 1-2.5 m to 0.08 px and 0.003 deg).
BoardSessionOptions CharucoSession(BoardSessionOptions options = {});
// A chessboard with circle markers is held as a ChArUco board is: a part of it counts.
BoardSessionOptions MarkedChessboardSession(BoardSessionOptions options = {});
// The session a team takes of a board of this kind ("chessboard", "charuco"; a chessboard
// with circle markers when the options say so).
BoardSessionOptions BoardSessionOf(const std::string& kind, const BoardSessionOptions& options);

// The placements for the rig, deterministic for the seed, without their images.
std::vector<BoardPlacement> PlanBoardSession(const SimRig& rig, uint64_t seed,
                                             const BoardSessionOptions& options);
// The same placements with both images rendered.
std::vector<BoardPlacement> RenderBoardSession(const SimRig& rig, uint64_t seed,
                                               const BoardSessionOptions& options);

// One camera's view of the board: its radiance, before the sensor. charuco_image: the ChArUco
// board as DrawCharucoBoard draws it (empty: a chessboard).
cv::Mat RenderBoardView(const CameraIntrinsics& camera, const Eigen::Isometry3d& camera_from_board,
                        const ChessboardOptions& board, bool board_in_view, int supersampling,
                        const cv::Mat& charuco_image = cv::Mat());

// One camera's view of a placement: its radiance, before the sensor. charuco_image:
// CharucoImageOf(options), drawn once for all placements.
cv::Mat RenderPlacementView(const SimRig& rig, const BoardPlacement& placement, Side side,
                            const BoardSessionOptions& options, const cv::Mat& charuco_image);
cv::Mat CharucoImageOf(const BoardSessionOptions& options);

// A rendered session written as a field team's camera would leave it, and its truth:
//   DIR/left/NN.png, DIR/right/NN.png  the pairs (Mono8), NN from 01, views without a board too
//   DIR/session.json                   the board (columns, rows, square) and the command that
//                                      calibrates the pair from these images
//   TRUTH/calibration.yaml             the rig's true calibration
//   TRUTH/board_session.json           per placement: the board's pose in the left camera,
//                                      whether a board is in view, whether it is blurred
Status WriteBoardSession(const SimRig& rig, uint64_t seed, const BoardSessionOptions& options,
                         const std::string& dir, const std::string& truth_dir);

}  // namespace ts::sim
