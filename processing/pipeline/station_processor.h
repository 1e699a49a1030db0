#pragma once
// The incremental station (DESIGN.md "Processing pipeline"): each pair is matched and
// intersected into L on a worker thread as soon as it is committed, while the capture goes on;
// Finish() runs the station-wide steps after the last pair. `process` on a finished station
// is the same object with no pair handed in: Finish() matches every pair itself (in parallel),
// and the products are the same to the bit either way.
//
// Threads: AddPair() and Finish() from one owner thread; the ProcessControl's callbacks also
// run on the worker.
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "core/result.h"
#include "processing/calibration/rig_tie_points.h"
#include "processing/pipeline/process_options.h"
#include "processing/pipeline/station_steps.h"
#include "processing/pipeline/step.h"
#include "processing/products/panorama.h"

namespace ts {

// What `process` made, beside the files: for callers that look further (benchmarks, tests).
struct ProcessResult {
  nlohmann::json report;             // as written to products/report.json
  ProcessSummary summary;            // why it ended; each step's time, counts, warnings
  PointCloud cloud;                  // every intersected point, in L
  std::vector<uint8_t> point_class;  // PointClass per point of the cloud
  Raster dem, dem_std;
  TerrainCorrection terrain_correction;
};

class StationProcessor {
 public:
  StationProcessor(std::string station_dir, ProcessOptions options, ProcessControl control = {});
  ~StationProcessor();  // stops and joins the worker
  StationProcessor(const StationProcessor&) = delete;
  StationProcessor& operator=(const StationProcessor&) = delete;

  // A pair just committed to the station's manifest, with its images as written (shared,
  // never modified). Returns at once; the pair is matched on the worker.
  void AddPair(const PairRecord& pair, const cv::Mat& left, const cv::Mat& right);

  // Waits for the pairs in hand, matches those of the manifest not handed in (or handed in
  // under another calibration), runs the station-wide steps and writes the products. On
  // failure or cancel: the error, naming the step (summary() says what each step did).
  Result<ProcessResult> Finish();
  const ProcessSummary& summary() const { return summary_; }

 private:
  struct Pending {
    PairRecord record;
    cv::Mat left, right;
  };
  void Work();
  bool MatchPairs(StepRunner* run, StationWork* w, StepSummary* s);
  // The stage checked on the matched pairs' seams (rig_check.h); with self_calibrate_rig the
  // pairs' points, the panorama and `in`'s calibration move to the adjusted stage.
  bool CheckRigStep(StationInputs* in, StationWork* w, StepSummary* s);
  // The pairs' left images: those in hand (handed in or decoded for matching, at the same
  // read-back), the others from disk.
  Result<std::vector<StereoPairImages>> LeftImages(const StationInputs& in,
                                                   const std::vector<PairRecord>& records) const;
  // The matched pairs, the cloud, the panorama and `in`'s calibration on `refined`'s stage; the
  // largest turn of a view (deg).
  double MoveToStage(const Calibration& refined, const std::vector<StereoPairImages>& left_images,
                     StationInputs* in, StationWork* w);

  const std::string dir_;
  const ProcessOptions options_;
  const ProcessControl control_;
  ProcessSummary summary_;

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Pending> queue_;
  bool busy_ = false, stopping_ = false;
  std::map<int, MatchedPair> matched_;  // by pair index
  std::map<int, StereoPairImages>
      left_images_;  // as handed in or decoded (no right image), for the rig
  std::unique_ptr<PanoramaBuilder> panorama_;  // of the matched pairs
  std::unique_ptr<RigTieFinder> tie_finder_;   // the matched pairs' tie points, for the rig
  std::string worker_calibration_sha256_;
  double worker_matching_s_ = 0.0;
  std::thread worker_;
};

// `process`: the products of a finished (or partly captured) station directory.
Result<ProcessResult> ProcessStation(const std::string& station_dir, const ProcessOptions& options,
                                     const ProcessControl& control = {});

}  // namespace ts
