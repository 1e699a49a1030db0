#include "processing/calibration/charuco.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cstdio>
#include <map>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "processing/calibration/saddle_refinement.h"

namespace ts {
namespace {

constexpr int kMinCorners = 6;
// The start's error, once the module's offset is removed, is about 0.1 px (the offset's spread
// on rendered boards): a refinement that moves a corner further has left its saddle.
constexpr double kMaxRefinementShiftPx = 0.5;
// The narrowest cross of pixels between a corner's markers a refinement uses (px).
constexpr double kMinCrossPx = 0.5;

cv::Ptr<cv::aruco::CharucoBoard> Board(const CharucoOptions& o) {
  return cv::aruco::CharucoBoard::create(
      o.corners.columns + 1, o.corners.rows + 1, static_cast<float>(o.corners.square),
      static_cast<float>(o.marker * o.corners.square),
      cv::aruco::getPredefinedDictionary(cv::aruco::DICT_5X5_1000));
}

// Smoothing spreads a marker's edge this far (px) into a window: about two of its sigmas and
// the gradient's own pixel.
double MarkerReachPx(double smoothing_px) { return 2.0 * smoothing_px + 1.5; }

// The board around one corner as the image shows it, from a homography fitted to the corner
// and its detected neighbours (the 3 x 3 corners about it): board coordinates in squares
// relative to the corner, and the shortest side a square shows there (px).
struct LocalBoard {
  bool known = false;
  cv::Matx33d board_from_image;
  double square_px = 0.0;
};

// The smaller singular value of the image's Jacobian with respect to the board at the corner.
double ShortestSidePx(const cv::Matx33d& image_from_board) {
  const cv::Matx33d& h = image_from_board;
  const double w = h(2, 2), x = h(0, 2) / w, y = h(1, 2) / w;
  Eigen::Matrix2d j;
  j << h(0, 0) - h(2, 0) * x, h(0, 1) - h(2, 1) * x, h(1, 0) - h(2, 0) * y, h(1, 1) - h(2, 1) * y;
  return Eigen::JacobiSVD<Eigen::Matrix2d>(j / w).singularValues()(1);
}

// False with fewer than four corners about it.
LocalBoard LocalBoardAt(const CharucoOptions& o, const std::map<int, cv::Point2f>& by_id, int id) {
  const int columns = o.corners.columns, rows = o.corners.rows;
  const int r0 = id / columns, c0 = id % columns;
  std::vector<cv::Point2f> board, image;
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc) {
      const int r = r0 + dr, c = c0 + dc;
      if (r < 0 || r >= rows || c < 0 || c >= columns) continue;
      const auto it = by_id.find(r * columns + c);
      if (it == by_id.end()) continue;
      board.emplace_back(dc, dr);
      image.push_back(it->second);
    }
  LocalBoard local;
  if (board.size() < 4) return local;
  const cv::Mat h = cv::findHomography(board, image, 0);
  if (h.empty()) return local;
  const cv::Matx33d image_from_board(h);
  local.known = true;
  local.board_from_image = image_from_board.inv();
  local.square_px = ShortestSidePx(image_from_board);
  return local;
}

// Refines the corners (saddle_refinement.h) with the markers left out: a corner's window
// reaches along its four edges up to a third of a square, its pixels only those of the cross
// between the two markers beside it, as the local homography places them. Where the white
// margin between corner and markers is too narrow for the smoothing's reach (the far side of a
// board at a grazing angle), the image is taken unsmoothed. A corner without the neighbours
// for a homography keeps a window inside that margin. A corner the refinement cannot fix, or
// moves further than the start's own error allows (it has left its saddle), is dropped, not
// kept wrong.
void RefineCharucoCorners(const cv::Mat& grey, const CharucoOptions& o,
                          const std::vector<std::vector<cv::Point2f>>& markers,
                          std::vector<int>* ids, std::vector<cv::Point2f>* found) {
  double smallest_marker = 1e30;
  for (const auto& m : markers)
    for (int k = 0; k < 4; ++k)
      smallest_marker = std::min<double>(smallest_marker, cv::norm(m[k] - m[(k + 1) % 4]));
  const double margin_squares = 0.5 * (1.0 - o.marker);
  std::map<int, cv::Point2f> by_id;
  for (size_t i = 0; i < ids->size(); ++i) by_id[(*ids)[i]] = (*found)[i];
  std::vector<LocalBoard> local;
  for (int id : *ids) {
    local.push_back(LocalBoardAt(o, by_id, id));
    if (!local.back().known) local.back().square_px = smallest_marker / o.marker;
  }
  std::vector<Eigen::Vector2d> corners;
  for (const cv::Point2f& p : *found) corners.emplace_back(p.x, p.y);
  const std::vector<Eigen::Vector2d> start = corners;
  std::vector<bool> done(ids->size(), false);
  SaddleRefinementOptions refinement;
  for (const double smoothing_px : {refinement.smoothing_px, 0.0}) {
    refinement.smoothing_px = smoothing_px;
    const double reach_px = MarkerReachPx(smoothing_px);
    std::vector<double> half(ids->size(), 0.0);
    for (size_t i = 0; i < ids->size(); ++i) {
      const double margin_px = margin_squares * local[i].square_px - reach_px;
      if (done[i] || margin_px < kMinCrossPx) continue;
      half[i] = local[i].known ? local[i].square_px / 3.0 : margin_px;
    }
    if (std::none_of(half.begin(), half.end(), [](double h) { return h > 0.0; })) continue;
    // Nearer than the margin (less the smoothing's reach) to one of the corner's edges.
    const SaddlePixelTest in_cross = [&](size_t i, const Eigen::Vector2d& p) {
      if (!local[i].known) return true;
      const cv::Vec3d b = local[i].board_from_image * cv::Vec3d(p.x(), p.y(), 1.0);
      const double u = std::abs(b[0] / b[2]), v = std::abs(b[1] / b[2]);
      return std::min(u, v) <= margin_squares - reach_px / local[i].square_px;
    };
    std::vector<Eigen::Vector2d> pass = corners;
    std::vector<bool> refined;
    RefineSaddles(grey, half, in_cross, refinement, &pass, &refined);
    for (size_t i = 0; i < ids->size(); ++i)
      if (refined[i]) {
        corners[i] = pass[i];
        done[i] = true;
      }
  }
  std::vector<cv::Point2f> kept_corners;
  std::vector<int> kept_ids;
  for (size_t i = 0; i < corners.size(); ++i)
    if (done[i] && (corners[i] - start[i]).norm() <= kMaxRefinementShiftPx) {
      kept_corners.emplace_back(corners[i].x(), corners[i].y());
      kept_ids.push_back((*ids)[i]);
    }
  *found = std::move(kept_corners);
  *ids = std::move(kept_ids);
}

}  // namespace

bool CharucoOptions::Check(std::string* why) const {
  if (!corners.Check(why)) return false;
  std::string err;
  if (!(marker > 0.1 && marker < 1.0)) err = "the marker must be 0.1-1 of a square";
  if ((corners.columns + 1) * (corners.rows + 1) / 2 > 1000)
    err = "at most 1000 markers (2000 squares) in the 5x5 dictionary";
  if (err.empty()) return true;
  if (why) *why = err;
  return false;
}

bool ParseCharucoSize(const std::string& text, CharucoOptions* options) {
  int x = 0, y = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &x, &y, &tail) != 2 || x < 3 || y < 3) return false;
  options->corners.columns = x - 1;
  options->corners.rows = y - 1;
  return true;
}

cv::Mat DrawCharucoBoard(const CharucoOptions& o, int pixels_per_square) {
  cv::Mat image;
  Board(o)->draw(cv::Size((o.corners.columns + 1) * pixels_per_square,
                          (o.corners.rows + 1) * pixels_per_square),
                 image, 0, 1);
  return image;
}

std::optional<TargetView> DetectCharuco(const cv::Mat& grey, const CharucoOptions& o) {
  const cv::Ptr<cv::aruco::CharucoBoard> board = Board(o);
  std::vector<std::vector<cv::Point2f>> markers, rejected;
  std::vector<int> marker_ids;
  const cv::Ptr<cv::aruco::DetectorParameters> parameters = cv::aruco::DetectorParameters::create();
  cv::aruco::detectMarkers(grey, board->dictionary, markers, marker_ids, parameters, rejected);
  if (marker_ids.empty()) return std::nullopt;
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(markers, marker_ids, grey, board, corners, ids);
  if (static_cast<int>(ids.size()) < kMinCorners ||
      cv::aruco::testCharucoCornersCollinear(board, ids))
    return std::nullopt;
  // The aruco module's corners sit half a pixel off the saddle points (measured on rendered
  // boards: +0.5, +0.5 px everywhere, to 0.1 px; OpenCV 4.6 adds 0.5 after its own
  // cornerSubPix, opencv/opencv#25539, mended upstream in 2026): that offset is removed first.
  for (cv::Point2f& c : corners) c -= cv::Point2f(0.5f, 0.5f);
  RefineCharucoCorners(grey, o, markers, &ids, &corners);
  if (static_cast<int>(ids.size()) < kMinCorners ||
      cv::aruco::testCharucoCornersCollinear(board, ids))
    return std::nullopt;
  TargetView view;
  for (size_t i = 0; i < ids.size(); ++i) {
    view.ids.push_back(ids[i]);
    view.pixels.emplace_back(corners[i].x, corners[i].y);
  }
  return view;
}

}  // namespace ts
