#include "sim/calibration_views.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "processing/geometry/rotation.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "sim/noise.h"

namespace ts::sim {
namespace {

// A printed board: its squares, and what is drawn in them.
struct BoardPrint {
  ChessboardOptions board;
  cv::Mat charuco;  // a ChArUco board as DrawCharucoBoard draws it; empty: a chessboard
  std::vector<Eigen::Vector2i> circle_markers;  // the squares with one (CircleMarkerCells)
  // Per square (i + 1, j + 1), i in -1 .. columns - 1: one colour all over (no marker in it).
  cv::Mat plain;
};

// The squares of one colour: a ChArUco square whose drawn block is, a chessboard's but those
// with a circle marker.
cv::Mat PlainSquares(const BoardPrint& p) {
  const ChessboardOptions& b = p.board;
  cv::Mat plain(b.rows + 1, b.columns + 1, CV_8UC1, cv::Scalar(1));
  for (const Eigen::Vector2i& cell : p.circle_markers)
    plain.at<uchar>(cell.y() + 1, cell.x() + 1) = 0;
  if (p.charuco.empty()) return plain;
  const int per_square = p.charuco.cols / (b.columns + 1);
  for (int j = 0; j <= b.rows; ++j)
    for (int i = 0; i <= b.columns; ++i) {
      double low = 0.0, high = 0.0;
      cv::minMaxLoc(p.charuco(cv::Rect(i * per_square, j * per_square, per_square, per_square)),
                    &low, &high);
      plain.at<uchar>(j, i) = (low > 127) == (high > 127);
    }
  return plain;
}

BoardPrint BoardPrintOf(const ChessboardOptions& board, const cv::Mat& charuco) {
  BoardPrint print{board, charuco, {}, {}};
  if (board.circle_markers && charuco.empty())
    for (const Eigen::Vector2i& cell : CircleMarkerCells(board))
      print.circle_markers.push_back(cell);
  print.plain = PlainSquares(print);
  return print;
}

// A cell of the board's plane (a square, or a square's worth of margin or wall beyond) that is
// one colour all over.
bool PlainCell(const BoardPrint& p, int64_t i, int64_t j) {
  const ChessboardOptions& b = p.board;
  if (i < -1 || j < -1 || i > b.columns - 1 || j > b.rows - 1) return true;
  return p.plain.at<uchar>(static_cast<int>(j + 1), static_cast<int>(i + 1)) != 0;
}

// A chessboard square's radiance: black or white, or inverted within a circle marker.
float SquareRadiance(const BoardPrint& p, double x, double y, double i, double j) {
  const bool black = static_cast<int64_t>(i + j) % 2 == 0;
  for (const Eigen::Vector2i& cell : p.circle_markers)
    if (cell.x() == i && cell.y() == j &&
        std::hypot(x / p.board.square - i - 0.5, y / p.board.square - j - 0.5) <
            0.5 * kCircleMarkerDiameter)
      return black ? kTargetWhite : kTargetBlack;
  return black ? kTargetBlack : kTargetWhite;
}

// The board's radiance at a point of its plane: squares from one square before the first inner
// corner to one after the last, a white margin of one square around them, a grey wall beyond.
// A ChArUco board's squares come from its drawn image (nearest pixel).
float BoardRadiance(const BoardPrint& p, double x, double y) {
  const ChessboardOptions& b = p.board;
  const cv::Mat& charuco = p.charuco;
  const double i = std::floor(x / b.square), j = std::floor(y / b.square);
  if (i < -2 || j < -2 || i > b.columns || j > b.rows) return kTargetBackground;
  if (i < -1 || j < -1 || i > b.columns - 1 || j > b.rows - 1) return kTargetWhite;
  if (charuco.empty()) return SquareRadiance(p, x, y, i, j);
  const double per_square = static_cast<double>(charuco.cols) / (b.columns + 1);
  const int u =
      std::clamp(static_cast<int>((x / b.square + 1.0) * per_square), 0, charuco.cols - 1);
  const int v =
      std::clamp(static_cast<int>((y / b.square + 1.0) * per_square), 0, charuco.rows - 1);
  return charuco.at<uchar>(v, u) > 127 ? kTargetWhite : kTargetBlack;
}

// A pose of the board in a camera's frame, its centre towards `anchor` of the frame ((-1, -1)
// the top left corner, (0, 0) the centre, (1, 1) the bottom right): as far as the whole board
// can reach there, times `reach` (a tilted board's near side is larger), or beyond the edge.
Eigen::Isometry3d PlaceBoard(std::mt19937_64& rng, const BoardSessionOptions& o,
                             const CameraIntrinsics& camera, const Eigen::Vector2d& anchor,
                             bool beyond, double reach) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double distance = o.min_distance_m + (o.max_distance_m - o.min_distance_m) * u(rng);
  const ChessboardOptions b = o.Board();
  const double scale = camera.principal_distance_px / distance;
  const double half_w = 0.5 * (b.columns + 3) * b.square * scale;
  const double half_h = 0.5 * (b.rows + 3) * b.square * scale;
  // A board running off the frame has its centre up to a tenth of the frame beyond the edge,
  // or, a board named by its circle markers, a tenth within (the markers are at its centre).
  const double beyond_room = o.circle_markers ? 0.4 : 0.6;
  const double room_x = beyond ? beyond_room * camera.width_px
                               : reach * std::max(0.0, 0.5 * camera.width_px - half_w);
  const double room_y = beyond ? beyond_room * camera.height_px
                               : reach * std::max(0.0, 0.5 * camera.height_px - half_h);
  // A hand's placement is not exact: a fifth of the room about the anchor.
  const auto towards = [&](double a) { return std::clamp(a + 0.2 * (2 * u(rng) - 1), -1.0, 1.0); };
  const double px = 0.5 * camera.width_px + room_x * towards(anchor.x());
  const double py = 0.5 * camera.height_px + room_y * towards(anchor.y());
  const Eigen::Vector3d centre = CameraModel(camera).RayFromPixel({px, py}).normalized() * distance;
  const double tilt = RadFromDeg(o.max_tilt_deg);
  const Eigen::Matrix3d facing =
      (Eigen::AngleAxisd(tilt * (2 * u(rng) - 1), Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(tilt * (2 * u(rng) - 1), Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.3 * (2 * u(rng) - 1), Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = facing;
  const Eigen::Vector3d board_centre(0.5 * (b.columns - 1) * b.square,
                                     0.5 * (b.rows - 1) * b.square, 0.0);
  pose.translation() = centre - facing * board_centre;
  return pose;
}

// The board's outline (with its margin) in the image, 10 points a side; false when a part of it
// is behind the camera or cannot be projected.
bool BoardOutline(const CameraModel& model, const Eigen::Isometry3d& camera_from_board,
                  const ChessboardOptions& b, std::vector<Eigen::Vector2d>* pixels) {
  const double x0 = -2 * b.square, y0 = -2 * b.square;
  const double x1 = (b.columns + 1) * b.square, y1 = (b.rows + 1) * b.square;
  for (int k = 0; k < 40; ++k) {
    const double t = (k % 10) / 10.0;
    const int side = k / 10;
    const Eigen::Vector3d p = side == 0   ? Eigen::Vector3d(x0 + t * (x1 - x0), y0, 0)
                              : side == 1 ? Eigen::Vector3d(x1, y0 + t * (y1 - y0), 0)
                              : side == 2 ? Eigen::Vector3d(x1 - t * (x1 - x0), y1, 0)
                                          : Eigen::Vector3d(x0, y1 - t * (y1 - y0), 0);
    Eigen::Vector2d pixel;
    if (!model.Project(camera_from_board * p, &pixel)) return false;
    pixels->push_back(pixel);
  }
  return true;
}

// The pixels the board (with its margin) can cover: its outline projected, widened by a few
// pixels for the curvature of its edges; the whole frame when some of it is behind the camera.
cv::Rect BoardExtent(const CameraModel& model, const Eigen::Isometry3d& camera_from_board,
                     const ChessboardOptions& b) {
  const CameraIntrinsics& c = model.intrinsics();
  const cv::Rect frame(0, 0, c.width_px, c.height_px);
  std::vector<Eigen::Vector2d> outline;
  if (!BoardOutline(model, camera_from_board, b, &outline)) return frame;
  Eigen::Vector2d low = Eigen::Vector2d::Constant(1e300), high = -low;
  for (const Eigen::Vector2d& pixel : outline) {
    low = low.cwiseMin(pixel);
    high = high.cwiseMax(pixel);
  }
  if (!(high.x() - low.x() < 1e5 && high.y() - low.y() < 1e5)) return frame;
  const cv::Rect widened(static_cast<int>(std::floor(low.x())) - 8,
                         static_cast<int>(std::floor(low.y())) - 8,
                         static_cast<int>(std::ceil(high.x() - low.x())) + 16,
                         static_cast<int>(std::ceil(high.y() - low.y())) + 16);
  return widened & frame;
}

// The whole board with its margin inside the frame: a chessboard can be found there.
bool BoardInside(const CameraIntrinsics& camera, const Eigen::Isometry3d& camera_from_board,
                 const ChessboardOptions& b) {
  const CameraModel model(camera);
  std::vector<Eigen::Vector2d> outline;
  if (!BoardOutline(model, camera_from_board, b, &outline)) return false;
  for (const Eigen::Vector2d& pixel : outline)
    if (!model.InImage(pixel)) return false;
  return true;
}

// The board's circle markers, with a square about them, inside the frame: the part of the
// board in view can be numbered there (a team holds such a board so that the capture finds it
// in both images).
bool MarkersInside(const CameraIntrinsics& camera, const Eigen::Isometry3d& camera_from_board,
                   const ChessboardOptions& b) {
  const CameraModel model(camera);
  const Eigen::Vector2i origin = CircleMarkerCells(b)[0];
  for (const int dc : {-1, 3})
    for (const int dr : {-1, 3}) {
      const Eigen::Vector3d corner((origin.x() + dc) * b.square, (origin.y() + dr) * b.square, 0);
      Eigen::Vector2d pixel;
      if (!model.Project(camera_from_board * corner, &pixel) || !model.InImage(pixel)) return false;
    }
  return true;
}

}  // namespace

bool BoardSessionOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  if (min_distance_m > max_distance_m) {
    if (why) *why = "min_distance_m must not exceed max_distance_m";
    return false;
  }
  if (charuco && circle_markers) {
    if (why) *why = "a board is either a ChArUco board or one with circle markers";
    return false;
  }
  return Board().Check(why);
}

cv::Mat RenderBoardView(const CameraIntrinsics& camera, const Eigen::Isometry3d& camera_from_board,
                        const ChessboardOptions& board, bool board_in_view, int supersampling,
                        const cv::Mat& charuco_image) {
  const CameraModel model(camera);
  const Eigen::Isometry3d board_from_camera = camera_from_board.inverse();
  const Eigen::Vector3d origin = board_from_camera.translation();
  cv::Mat radiance(camera.height_px, camera.width_px, CV_32FC1, cv::Scalar(kTargetBackground));
  if (!board_in_view) return radiance;
  const cv::Rect extent = BoardExtent(model, camera_from_board, board);
  const BoardPrint print = BoardPrintOf(board, charuco_image);
  // Where a pixel's point meets the board's plane; false behind the camera.
  const auto on_board = [&](const Eigen::Vector2d& pixel, Eigen::Vector2d* point) {
    const Eigen::Vector3d d = board_from_camera.linear() * model.RayFromPixel(pixel);
    const double t = -origin.z() / d.z();
    *point = (origin + t * d).head<2>();
    return t > 0.0;
  };
  const int s = supersampling;
  const auto sampled = [&](int x, int y) {
    double sum = 0.0;
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        Eigen::Vector2d point;
        sum += on_board({x - 0.5 + (i + 0.5) / s, y - 0.5 + (j + 0.5) / s}, &point)
                   ? BoardRadiance(print, point.x(), point.y())
                   : kTargetBackground;
      }
    return static_cast<float>(sum / (s * s));
  };
  // A pixel whose four corners meet the plane in one plain cell lies in it (the cell is convex,
  // and a pixel's edges are straight on the plane to far below a pixel): its samples would all
  // be the cell's colour. Only pixels across an edge are sampled.
  const auto cell_of_corner = [&](int x, int y, Eigen::Vector2d* point) -> Eigen::Vector2i {
    if (!on_board({x - 0.5, y - 0.5}, point)) return {INT32_MIN, INT32_MIN};
    const double i = std::floor(point->x() / board.square),
                 j = std::floor(point->y() / board.square);
    if (!(std::abs(i) < 1e6 && std::abs(j) < 1e6)) return {INT32_MIN, INT32_MIN};
    return {static_cast<int>(i), static_cast<int>(j)};
  };
  cv::parallel_for_(cv::Range(extent.y, extent.y + extent.height), [&](const cv::Range& rows) {
    std::vector<Eigen::Vector2i> above(extent.width + 1), below(extent.width + 1);
    std::vector<Eigen::Vector2d> point_above(extent.width + 1), point_below(extent.width + 1);
    for (int x = 0; x <= extent.width; ++x)
      above[x] = cell_of_corner(extent.x + x, rows.start, &point_above[x]);
    for (int y = rows.start; y < rows.end; ++y) {
      for (int x = 0; x <= extent.width; ++x)
        below[x] = cell_of_corner(extent.x + x, y + 1, &point_below[x]);
      for (int x = 0; x < extent.width; ++x) {
        const Eigen::Vector2i cell = above[x];
        const bool one_plain_cell = cell.x() != INT32_MIN && above[x + 1] == cell &&
                                    below[x] == cell && below[x + 1] == cell &&
                                    PlainCell(print, cell.x(), cell.y());
        radiance.at<float>(y, extent.x + x) =
            one_plain_cell ? BoardRadiance(print, point_above[x].x(), point_above[x].y())
                           : sampled(extent.x + x, y);
      }
      std::swap(above, below);
      std::swap(point_above, point_below);
    }
  });
  return radiance;
}

BoardSessionOptions CharucoSession(BoardSessionOptions o) {
  o.charuco = true;
  o.circle_markers = false;
  o.beyond_share = 0.4;
  o.min_distance_m = 1.0;
  o.max_distance_m = 2.5;
  return o;
}

BoardSessionOptions MarkedChessboardSession(BoardSessionOptions o) {
  o = CharucoSession(o);
  o.charuco = false;
  o.circle_markers = true;
  return o;
}

BoardSessionOptions BoardSessionOf(const std::string& kind, const BoardSessionOptions& o) {
  if (kind == "charuco") return CharucoSession(o);
  return o.circle_markers ? MarkedChessboardSession(o) : o;
}

std::vector<BoardPlacement> PlanBoardSession(const SimRig& rig, uint64_t seed,
                                             const BoardSessionOptions& o) {
  std::mt19937_64 rng(Hash(seed, 0xB0A2D, 0x5E55));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const StereoRig& truth = rig.truth.rig;
  const Eigen::Isometry3d right_from_left = truth.RightFromLeftCamera();
  std::vector<BoardPlacement> session;
  for (int k = 0; k < o.placements; ++k) {
    BoardPlacement p;
    char name[16];
    std::snprintf(name, sizeof(name), "%02d", k + 1);
    p.name = name;
    // A team is told to hold the board at each part of each camera's frame in turn (the
    // corners, where the distortion is largest, the edges' middles, the centre), where both
    // cameras see all of it, except where a board running off the frame is wanted: a few tries
    // find such a pose, nearer the frame's centre each time.
    const bool beyond = u(rng) < o.beyond_share;
    const Eigen::Vector2d anchor((k % 9) % 3 - 1, (k % 9) / 3 - 1);
    const bool aim_right = (k / 9) % 2 == 1;
    const Eigen::Isometry3d left_from_aim =
        aim_right ? right_from_left.inverse() : Eigen::Isometry3d::Identity();
    // A board numbered by its circle markers must have them in both frames.
    const auto in_both = [&](const auto& inside) {
      return inside(truth.left, p.left_from_board, o.Board()) &&
             inside(truth.right, right_from_left * p.left_from_board, o.Board());
    };
    constexpr int kAttempts = 50;
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
      p.left_from_board =
          left_from_aim * PlaceBoard(rng, o, aim_right ? truth.right : truth.left, anchor, beyond,
                                     1.0 - static_cast<double>(attempt) / kAttempts);
      if ((!o.circle_markers || in_both(MarkersInside)) && (beyond || in_both(BoardInside))) break;
    }
    p.board = u(rng) >= o.empty_share;
    p.blurred = u(rng) < o.blurred_share;
    session.push_back(std::move(p));
  }
  return session;
}

cv::Mat RenderPlacementView(const SimRig& rig, const BoardPlacement& p, Side side,
                            const BoardSessionOptions& o, const cv::Mat& charuco_image) {
  const StereoRig& truth = rig.truth.rig;
  const bool left = side == Side::kLeft;
  cv::Mat radiance =
      RenderBoardView(left ? truth.left : truth.right,
                      left ? p.left_from_board : truth.RightFromLeftCamera() * p.left_from_board,
                      o.Board(), p.board, o.supersampling, charuco_image);
  if (p.blurred) cv::GaussianBlur(radiance, radiance, cv::Size(), 1.5);
  return radiance;
}

cv::Mat CharucoImageOf(const BoardSessionOptions& o) {
  // Fine enough that a sample never straddles two of the image's pixels' worth of a square.
  return o.charuco ? DrawCharucoBoard(o.Charuco(), 200) : cv::Mat();
}

std::vector<BoardPlacement> RenderBoardSession(const SimRig& rig, uint64_t seed,
                                               const BoardSessionOptions& o) {
  std::vector<BoardPlacement> session = PlanBoardSession(rig, seed, o);
  const cv::Mat charuco = CharucoImageOf(o);
  for (size_t k = 0; k < session.size(); ++k) {
    BoardPlacement& p = session[k];
    for (Side side : {Side::kLeft, Side::kRight}) {
      const bool left = side == Side::kLeft;
      (left ? p.left : p.right) =
          ExposeImage(RenderPlacementView(rig, p, side, o, charuco),
                      left ? rig.truth.rig.left : rig.truth.rig.right, rig.sensor(side),
                      o.exposure_us, 0.0, PixelFormat::kMono8, Hash(seed, k, left ? 1 : 2));
    }
  }
  return session;
}

Status WriteBoardSession(const SimRig& rig, uint64_t seed, const BoardSessionOptions& o,
                         const std::string& dir, const std::string& truth_dir) {
  namespace fs = std::filesystem;
  std::string why;
  if (!o.Check(&why)) return Error{"board session: " + why};
  std::error_code ec;
  for (const fs::path& d : {fs::path(dir) / "left", fs::path(dir) / "right", fs::path(truth_dir)})
    if (fs::create_directories(d, ec); ec) return Error{d.string() + ": " + ec.message()};
  const std::vector<BoardPlacement> session = RenderBoardSession(rig, seed, o);
  nlohmann::json placements = nlohmann::json::array();
  for (const BoardPlacement& p : session) {
    for (const auto& [side, image] : {std::pair{"left", &p.left}, std::pair{"right", &p.right}}) {
      const fs::path file = fs::path(dir) / side / (p.name + ".png");
      if (!cv::imwrite(file.string(), *image)) return Error{file.string() + ": cannot write"};
    }
    std::vector<double> pose;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) pose.push_back(p.left_from_board.matrix()(r, c));
    placements.push_back(
        {{"name", p.name}, {"board", p.board}, {"blurred", p.blurred}, {"left_from_board", pose}});
  }
  char board[64];
  if (o.charuco)
    std::snprintf(board, sizeof(board), "--charuco %dx%d --marker %g", o.columns + 1, o.rows + 1,
                  o.marker);
  else
    std::snprintf(board, sizeof(board), "--chessboard %dx%d%s", o.columns, o.rows,
                  o.circle_markers ? " --circle-markers" : "");
  const nlohmann::json description = {
      {"board",
       {{"columns", o.columns},
        {"rows", o.rows},
        {"square_m", o.square_m},
        {"charuco", o.charuco},
        {"marker", o.marker},
        {"circle_markers", o.circle_markers}}},
      {"placements", o.placements},
      {"calibrate", "topostation calibrate stereo --left '" + dir + "/left/*.png' --right '" + dir +
                        "/right/*.png' " + board + " --square " + std::to_string(o.square_m) +
                        " --out CAL.yaml"}};
  if (Status s = WriteFileAtomically((fs::path(dir) / "session.json").string(),
                                     description.dump(2) + "\n");
      !s)
    return s;
  if (Status s =
          SaveCalibrationYaml(rig.truth, (fs::path(truth_dir) / "calibration.yaml").string());
      !s)
    return s;
  const nlohmann::json truth = {
      {"seed", seed}, {"options", DeclaredOptionsToJson(o)}, {"placements", placements}};
  return WriteFileAtomically((fs::path(truth_dir) / "board_session.json").string(),
                             truth.dump(2) + "\n");
}

}  // namespace ts::sim
