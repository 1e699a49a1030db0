#include "processing/calibration/charuco.h"

#include <algorithm>
#include <cstdio>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>

namespace ts {
namespace {

constexpr int kMinCorners = 6;
// The start's error, once the module's offset is removed, is about 0.1 px (the offset's spread
// on rendered boards): a refinement that moves a corner further has left its saddle.
constexpr double kMaxRefinementShiftPx = 0.5;

cv::Ptr<cv::aruco::CharucoBoard> Board(const CharucoOptions& o) {
  return cv::aruco::CharucoBoard::create(
      o.corners.columns + 1, o.corners.rows + 1, static_cast<float>(o.corners.square),
      static_cast<float>(o.marker * o.corners.square),
      cv::aruco::getPredefinedDictionary(cv::aruco::DICT_5X5_1000));
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
  // cornerSubPix, opencv/opencv#25539, mended upstream in 2026): that offset is removed first. Then
  // the gradient-orthogonality refinement the chessboards get (chessboard.cc) finds the saddles,
  // its window inside the white margin between a corner and the nearest marker ((1 - marker)
  // / 2 of a square), where only the corner's edges are. On a board seen at a grazing angle
  // that margin is a few pixels and a window may reach a marker's edge: a corner the
  // refinement moves further than the start's own error allows is dropped, not kept wrong.
  for (cv::Point2f& c : corners) c -= cv::Point2f(0.5f, 0.5f);
  double smallest_marker = 1e30;
  for (const auto& m : markers)
    for (int k = 0; k < 4; ++k)
      smallest_marker = std::min<double>(smallest_marker, cv::norm(m[k] - m[(k + 1) % 4]));
  const double square_px = smallest_marker / o.marker;
  const int half = std::min(5, static_cast<int>(0.5 * (1.0 - o.marker) * square_px));
  if (half >= 2) {
    const std::vector<cv::Point2f> start = corners;
    cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 50, 1e-4));
    std::vector<cv::Point2f> kept_corners;
    std::vector<int> kept_ids;
    for (size_t i = 0; i < corners.size(); ++i)
      if (cv::norm(corners[i] - start[i]) <= kMaxRefinementShiftPx) {
        kept_corners.push_back(corners[i]);
        kept_ids.push_back(ids[i]);
      }
    corners = std::move(kept_corners);
    ids = std::move(kept_ids);
    if (static_cast<int>(ids.size()) < kMinCorners ||
        cv::aruco::testCharucoCornersCollinear(board, ids))
      return std::nullopt;
  }
  TargetView view;
  for (size_t i = 0; i < ids.size(); ++i) {
    view.ids.push_back(ids[i]);
    view.pixels.emplace_back(corners[i].x, corners[i].y);
  }
  return view;
}

}  // namespace ts
