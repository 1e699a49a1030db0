#pragma once
// Calibration views of a printed board, taken on demand (`capture --calibration chessboard|
// charuco`). The stage stands still while a helper holds the board at one place after
// another in front of the rig. For each pair the operator asks for (Enter on a terminal, or
// every few seconds) both cameras are triggered together (pair_sequencer.h), the board is
// looked for in both images at once, and the operator is told what was found and how much of
// each frame the boards kept so far cover (the distortion is measured only there). A pair is
// kept when the board is in either image, and written before the next is taken; pairs are
// numbered on from those already in the directory, so a session stopped at any moment goes on
// where it stopped, its coverage counted again from the images.
//
//   DIR/left/NN.png, DIR/right/NN.png   the kept pairs, NN from 01 (`calibrate stereo --left
//                                       'DIR/left/*.png' --right 'DIR/right/*.png'`)
//   DIR/session.json                    the board, each pair's corners found, the coverage and
//                                       the command that calibrates the pair
#include <memory>
#include <string>

#include "acquisition/capture.h"
#include "processing/calibration/calibration_board.h"
#include "processing/calibration/target_views.h"

namespace ts {

class PairSequencer;

struct BoardPair {
  std::string name;                         // "07": the files' number (of a kept pair)
  int corners_left = 0, corners_right = 0;  // found; 0: no board in that image
  bool kept = false;
  double exposure_us = 0.0;
  // Of the frame, by the boards of every pair kept so far (this one included).
  FrameCoverage left_coverage, right_coverage;
  // "pair 07: 176 corners left, 160 right; frames covered 62 % / 58 % (edges 40 % / 35 %)".
  std::string Summary() const;
};

class BoardCapture {
 public:
  // Starts both cameras (CaptureOptions: exposure control, frame timeouts, retries) and reads
  // the pairs already in `dir`. Errors name the device or the file.
  static Result<std::unique_ptr<BoardCapture>> Open(Camera& left, Camera& right,
                                                    const std::string& dir,
                                                    const CalibrationBoard& board,
                                                    const CaptureOptions& options);
  ~BoardCapture();

  // One pair: taken, checked, kept (written, session.json updated) when the board is in it.
  Result<BoardPair> TakePair();
  int kept() const { return static_cast<int>(records_.size()); }
  const CaptureSummary& summary() const { return summary_; }

 private:
  BoardCapture(Camera& left, Camera& right, std::string dir, CalibrationBoard board,
               CaptureOptions options);
  Status ReadKeptPairs();
  Status WriteSession() const;

  Camera& left_;
  Camera& right_;
  std::string dir_;
  CalibrationBoard board_;
  CaptureOptions options_;
  CaptureSummary summary_;
  std::function<void(const CaptureEvent&)> no_progress_;
  std::unique_ptr<PairSequencer> sequencer_;
  TargetViews left_views_, right_views_;  // the boards of the kept pairs
  std::vector<BoardPair> records_;        // the kept pairs
  bool started_ = false;                  // a camera was started: both are stopped at the end
};

}  // namespace ts
