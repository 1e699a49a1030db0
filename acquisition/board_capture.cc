#include "acquisition/board_capture.h"

#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "acquisition/pair_sequencer.h"
#include "core/log.h"
#include "processing/io/atomic_file.h"
#include "processing/io/image_file.h"

namespace ts {
namespace {

namespace fs = std::filesystem;

std::string FileNumber(int n) { return fmt::format("{:02d}", n); }

// The flags that name the board to `calibrate` (station/board_flags.h).
std::string BoardFlagsOf(const CalibrationBoard& b) {
  if (b.charuco)
    return fmt::format("--charuco {}x{} --marker {} --square {}", b.charuco->corners.columns + 1,
                       b.charuco->corners.rows + 1, b.charuco->marker, b.charuco->corners.square);
  return fmt::format("--chessboard {}x{} --square {}{}", b.chessboard.columns, b.chessboard.rows,
                     b.chessboard.square, b.chessboard.circle_markers ? " --circle-markers" : "");
}

nlohmann::json CoverageJson(const FrameCoverage& c) {
  return {{"share", c.share}, {"edges_share", c.border_share}};
}

}  // namespace

std::string BoardPair::Summary() const {
  const std::string found =
      corners_left + corners_right == 0
          ? "no board in either image, not kept"
          : fmt::format(
                "{} corners left, {} right{}", corners_left, corners_right,
                corners_left == 0 || corners_right == 0 ? " (board in one image only)" : "");
  return fmt::format("pair {}: {}; frames covered {:.0f} % / {:.0f} % (edges {:.0f} % / {:.0f} %)",
                     name, found, 100.0 * left_coverage.share, 100.0 * right_coverage.share,
                     100.0 * left_coverage.border_share, 100.0 * right_coverage.border_share);
}

BoardCapture::BoardCapture(Camera& left, Camera& right, std::string dir, CalibrationBoard board,
                           CaptureOptions options)
    : left_(left),
      right_(right),
      dir_(std::move(dir)),
      board_(std::move(board)),
      options_(std::move(options)) {
  sequencer_ = std::make_unique<PairSequencer>(left_, right_, options_, no_progress_, &summary_);
  sequencer_->exposure_us = options_.initial_exposure_us;
  for (TargetViews* v : {&left_views_, &right_views_}) v->target = board_.Corners();
}

BoardCapture::~BoardCapture() {
  if (!started_) return;
  for (Camera* c : {&left_, &right_})
    if (Status s = c->Stop(); !s) Log().warn("{}", s.error());
}

Result<std::unique_ptr<BoardCapture>> BoardCapture::Open(Camera& left, Camera& right,
                                                         const std::string& dir,
                                                         const CalibrationBoard& board,
                                                         const CaptureOptions& options) {
  std::string why;
  if (!options.Check(&why)) return Error{"capture: " + why};
  std::error_code ec;
  for (const char* side : {"left", "right"})
    if (fs::create_directories(fs::path(dir) / side, ec); ec)
      return Error{(fs::path(dir) / side).string() + ": cannot create: " + ec.message()};
  std::unique_ptr<BoardCapture> capture(new BoardCapture(left, right, dir, board, options));
  if (Status s = capture->ReadKeptPairs(); !s) return Error{s.error()};
  CameraSettings settings;
  settings.format = options.format;
  settings.exposure_us = capture->sequencer_->exposure_us;
  settings.gain_db = options.gain_db;
  for (Camera* c : {&left, &right}) {
    if (Status s = c->Configure(settings); !s) return Error{s.error()};
    if (Status s = c->Start(); !s) return Error{s.error()};
    capture->started_ = true;
  }
  return capture;
}

// The pairs a stopped session left: both images there, their boards found again.
Status BoardCapture::ReadKeptPairs() {
  for (int n = 1;; ++n) {
    const std::string name = FileNumber(n) + ".png";
    const fs::path left_file = fs::path(dir_) / "left" / name;
    const fs::path right_file = fs::path(dir_) / "right" / name;
    if (!fs::exists(left_file) || !fs::exists(right_file)) return {};
    BoardPair pair;
    pair.name = FileNumber(n);
    pair.kept = true;
    for (const fs::path& file : {left_file, right_file}) {
      const cv::Mat grey = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
      if (grey.empty()) return Error{file.string() + ": not a readable image"};
      TargetViews& views = file == left_file ? left_views_ : right_views_;
      if (views.width_px == 0) views.width_px = grey.cols, views.height_px = grey.rows;
      std::optional<TargetView> view = DetectBoard(grey, board_);
      if (!view) continue;
      view->name = name;
      view->placement = n - 1;
      (file == left_file ? pair.corners_left : pair.corners_right) =
          static_cast<int>(view->pixels.size());
      views.views.push_back(std::move(*view));
    }
    pair.left_coverage = left_views_.Coverage();
    pair.right_coverage = right_views_.Coverage();
    records_.push_back(pair);
  }
}

Result<BoardPair> BoardCapture::TakePair() {
  const int index = kept();  // the pair's number in the files, from 0
  Result<PairFrames> frames = sequencer_->TakePair(index, 0);
  if (!frames) return Error{frames.error()};
  BoardPair pair;
  pair.name = FileNumber(index + 1);
  pair.exposure_us = sequencer_->exposure_us;
  const cv::Mat* images[2] = {&frames->left.image, &frames->right.image};
  for (int i = 0; i < 2; ++i) {
    TargetViews& views = i == 0 ? left_views_ : right_views_;
    const cv::Mat& image = *images[i];
    if (views.width_px == 0) views.width_px = image.cols, views.height_px = image.rows;
    if (image.cols != views.width_px || image.rows != views.height_px)
      return Error{fmt::format("{}: {}x{} pixels, the pairs already in {} have {}x{}",
                               (i == 0 ? left_ : right_).Describe(), image.cols, image.rows, dir_,
                               views.width_px, views.height_px)};
  }
  // The two images are searched side by side: the detector keeps a core busy only in part, and
  // the operator waits for the pair's verdict before moving the board.
  std::optional<TargetView> found[2];
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      cv::Mat grey = *images[i];
      if (grey.depth() == CV_16U) images[i]->convertTo(grey, CV_8U, 1.0 / 256.0);
      found[i] = DetectBoard(grey, board_);
    }
  });
  pair.corners_left = found[0] ? static_cast<int>(found[0]->pixels.size()) : 0;
  pair.corners_right = found[1] ? static_cast<int>(found[1]->pixels.size()) : 0;
  pair.kept = found[0] || found[1];
  if (pair.kept) {
    for (int i = 0; i < 2; ++i) {
      const fs::path file = fs::path(dir_) / (i == 0 ? "left" : "right") / (pair.name + ".png");
      if (Result<std::string> sha = WritePngAtomically(*images[i], file.string()); !sha)
        return Error{sha.error()};
      if (!found[i]) continue;
      found[i]->name = pair.name + ".png";
      found[i]->placement = index;
      (i == 0 ? left_views_ : right_views_).views.push_back(std::move(*found[i]));
    }
  }
  pair.left_coverage = left_views_.Coverage();
  pair.right_coverage = right_views_.Coverage();
  if (pair.kept) {
    records_.push_back(pair);
    if (Status s = WriteSession(); !s) return Error{s.error()};
  }
  return pair;
}

Status BoardCapture::WriteSession() const {
  nlohmann::json pairs = nlohmann::json::array();
  for (const BoardPair& p : records_)
    pairs.push_back({{"name", p.name},
                     {"corners_left", p.corners_left},
                     {"corners_right", p.corners_right},
                     {"exposure_us", p.exposure_us}});
  const std::string in = fs::path(dir_).string();
  const nlohmann::json session = {
      {"board", board_.Describe()},
      {"pairs", pairs},
      {"coverage",
       {{"left", CoverageJson(left_views_.Coverage())},
        {"right", CoverageJson(right_views_.Coverage())}}},
      {"calibrate", "topostation calibrate stereo --left '" + in + "/left/*.png' --right '" + in +
                        "/right/*.png' " + BoardFlagsOf(board_) + " --out CAL.yaml"}};
  return WriteFileAtomically((fs::path(dir_) / "session.json").string(), session.dump(2) + "\n");
}

}  // namespace ts
