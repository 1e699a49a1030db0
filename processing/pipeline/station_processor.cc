#include "processing/pipeline/station_processor.h"

#include <algorithm>
#include <atomic>

#include <fmt/format.h>

#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/sha256.h"
#include "processing/pipeline/process_report.h"
#include "processing/pipeline/products.h"
#include "processing/pipeline/rig_check.h"
#include "processing/products/seams_image.h"

namespace ts {
namespace {

// The steps of `process` after the pairs are matched, in order (the method of DESIGN.md).
using StationStep = bool (*)(const ProcessOptions&, StationWork*, StepSummary*);
const std::pair<const char*, StationStep> kStationSteps[] = {
    {"blunder_filter", FilterHeightBlunders},
    {"sight_line_objects", FindObjectsAlongSightLines},
    {"ground_filter", FilterGroundPoints},
    {"underside_patches", RemoveUndersidePatches},
    {"seen_through_ground", RemovePointsSeenThroughGround},
    {"kriging", KrigeStationDem},
    {"horizon_limit", LimitDemToHorizon},
    {"free_space", KeepBelowSightLines},
    {"ground_room", AddGroundRoom},
    {"sight_tilt_sigma", AddSightTiltSigma},
    {"terrain_correction", CorrectTerrain},
    {"products", [](const ProcessOptions& o, StationWork* w,
                    StepSummary* s) { return WriteProducts(o, *w, s); }},
};
// With load, matching, rig and report.
constexpr int kStepCount = 4 + static_cast<int>(std::size(kStationSteps));

std::vector<PairRecord> InPairOrder(std::vector<PairRecord> records) {
  std::sort(records.begin(), records.end(),
            [](const PairRecord& a, const PairRecord& b) { return a.index < b.index; });
  return records;
}

std::string SeamsLine(const RigSeams& seams) {
  return fmt::format(
      "{:.0f} % of {} tie points within 2 of their predicted sigma (median {:.2f} px, {:.1f} mm)",
      100 * seams.within_2_sigma, seams.ties.size(), seams.median_px, seams.median_mm);
}

}  // namespace

StationProcessor::StationProcessor(std::string station_dir, ProcessOptions options,
                                   ProcessControl control)
    : dir_(std::move(station_dir)), options_(std::move(options)), control_(std::move(control)) {}

StationProcessor::~StationProcessor() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void StationProcessor::AddPair(const PairRecord& pair, const cv::Mat& left, const cv::Mat& right) {
  {
    std::lock_guard lock(mutex_);
    queue_.push_back({pair, left, right});
    if (!worker_.joinable()) worker_ = std::thread([this] { Work(); });
  }
  changed_.notify_all();
}

void StationProcessor::Work() {
  std::optional<StationInputs> inputs;
  std::unique_ptr<Rectification> rectification;
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_ || control_.StopRequested()) break;
    Pending pending = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    const auto t0 = std::chrono::steady_clock::now();
    // The manifest holds the first pair by now: the calibration is read as Finish() reads it.
    // A pair that cannot be matched here is matched again by Finish(), which says why.
    if (!inputs) {
      Result<StationInputs> loaded =
          LoadStationInputs(dir_, options_.calibration_file, options_.gcp_file,
                            options_.set_up_from_calibration_file);
      if (loaded) {
        inputs = std::move(*loaded);
        rectification = std::make_unique<Rectification>(Rectify(inputs->calibration.rig));
        std::lock_guard relock(mutex_);
        panorama_ = std::make_unique<PanoramaBuilder>(inputs->calibration, options_.panorama);
        tie_finder_ = std::make_unique<RigTieFinder>(inputs->calibration, options_.rig_ties);
      }
    }
    std::optional<MatchedPair> matched;
    const StereoPairImages images{pending.record.index, pending.record.readback.pan_deg,
                                  pending.record.readback.tilt_deg, pending.left, pending.right};
    if (inputs) {
      try {
        matched = MatchPairIntoL(inputs->calibration, *rectification, images, options_.matching);
        panorama_->Add({images});  // only this thread adds while it runs
        tie_finder_->Add({{images.index, images.pan_deg, images.tilt_deg, images.left, {}}},
                         {*matched});
      } catch (const std::exception&) {
        matched.reset();
      }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    lock.lock();
    busy_ = false;
    worker_matching_s_ += seconds;
    if (matched) {
      worker_calibration_sha256_ = inputs->calibration_sha256;
      matched_[images.index] = std::move(*matched);
      left_images_[images.index] = {images.index, images.pan_deg, images.tilt_deg, images.left,
                                    cv::Mat()};
    }
    ProcessProgress progress{"matching",
                             0,
                             0,
                             static_cast<int>(matched_.size()),
                             static_cast<int>(matched_.size() + queue_.size()),
                             0.0};
    lock.unlock();
    if (control_.progress) control_.progress(progress);
    changed_.notify_all();
    lock.lock();
  }
  busy_ = false;
  changed_.notify_all();
}

bool StationProcessor::MatchPairs(StepRunner* run, StationWork* w, StepSummary* s) {
  const StationInputs& in = *w->inputs;
  {  // the pairs handed in are matched, or the worker has stopped
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] {
      return (queue_.empty() && !busy_) || stopping_ || control_.StopRequested();
    });
    if (worker_calibration_sha256_ != in.calibration_sha256 || !panorama_) {
      matched_.clear();
      panorama_ = std::make_unique<PanoramaBuilder>(in.calibration, options_.panorama);
      tie_finder_ = std::make_unique<RigTieFinder>(in.calibration, options_.rig_ties);
    }
  }
  const std::vector<PairRecord> records = InPairOrder(in.manifest.pairs);
  std::vector<const PairRecord*> missing;  // not handed in, or at another read-back
  for (const PairRecord& p : records) {
    const auto m = matched_.find(p.index);
    if (m == matched_.end() || m->second.pan_deg != p.readback.pan_deg ||
        m->second.tilt_deg != p.readback.tilt_deg)
      missing.push_back(&p);
  }
  const int matched_before = static_cast<int>(records.size() - missing.size());
  if (!missing.empty()) {
    std::vector<StereoPairImages> images(missing.size());
    std::vector<std::string> errors(missing.size());
    cv::parallel_for_(cv::Range(0, static_cast<int>(missing.size())), [&](const cv::Range& range) {
      for (int i = range.start; i < range.end; ++i) {
        Result<StereoPairImages> loaded = LoadPairImages(in, *missing[i]);
        if (loaded)
          images[i] = std::move(*loaded);
        else
          errors[i] = loaded.error();
      }
    });
    for (const std::string& e : errors)
      if (!e.empty()) return s->message = e, false;
    std::atomic<int> done{matched_before};
    const int total = static_cast<int>(records.size());
    std::vector<MatchedPair> results =
        MatchPairsIntoL(in.calibration, Rectify(in.calibration.rig), images, options_.matching,
                        control_.should_stop, [&] { run->ReportPairs(++done, total); });
    if (control_.StopRequested()) return false;
    for (MatchedPair& m : results) matched_[m.index] = std::move(m);
    for (StereoPairImages& p : images) p.right = cv::Mat();  // the panorama needs the left ones
    panorama_->Add(images);
    // The rig step needs them too: decoded once.
    for (StereoPairImages& p : images) left_images_[p.index] = std::move(p);
  }
  nlohmann::json per_pair = nlohmann::json::array();
  for (const PairRecord& p : records) {
    const MatchedPair& m = matched_.at(p.index);
    w->cloud.insert(w->cloud.end(), m.cloud.begin(), m.cloud.end());
    w->pairs.push_back({m.index, m.pan_deg, m.tilt_deg, {}, {}});
    per_pair.push_back({{"pair", p.index},
                        {"interest_points", m.summary.points},
                        {"matched", m.summary.fitting},
                        {"across_occlusion_edges", m.summary.consistent - m.summary.one_surface},
                        {"misfitting", m.summary.one_surface - m.summary.fitting},
                        {"matching_s", m.summary.matching_s}});
    if (m.summary.fitting < 1000)
      s->warnings.push_back("pair " + std::to_string(p.index) + " gave only " +
                            std::to_string(m.summary.fitting) + " matches");
  }
  w->panorama = panorama_->Image();
  s->counts = {{"pairs", records.size()},
               {"matched_during_capture", matched_before},
               {"matching_during_capture_s", worker_matching_s_},
               {"points", w->cloud.size()},
               {"per_pair", per_pair}};
  return true;
}

Result<std::vector<StereoPairImages>> StationProcessor::LeftImages(
    const StationInputs& in, const std::vector<PairRecord>& records) const {
  std::vector<StereoPairImages> images(records.size());
  std::vector<std::string> errors(records.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(records.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const PairRecord& p = records[i];
      const auto kept = left_images_.find(p.index);
      if (kept != left_images_.end() && kept->second.pan_deg == p.readback.pan_deg &&
          kept->second.tilt_deg == p.readback.tilt_deg) {
        images[i] = kept->second;
        continue;
      }
      Result<StereoPairImages> loaded = LoadPairImages(in, p);
      if (loaded) {
        images[i] = std::move(*loaded);
        images[i].right = cv::Mat();
      } else {
        errors[i] = loaded.error();
      }
    }
  });
  for (const std::string& e : errors)
    if (!e.empty()) return Error{e};
  return images;
}

double StationProcessor::MoveToStage(const Calibration& refined,
                                     const std::vector<StereoPairImages>& left_images,
                                     StationInputs* in, StationWork* w) {
  for (auto& [index, pair] : matched_) MovePairPoints(in->calibration, refined, &pair);
  w->cloud.clear();
  for (const StereoPairImages& p : left_images) {
    const PointCloud& cloud = matched_.at(p.index).cloud;
    w->cloud.insert(w->cloud.end(), cloud.begin(), cloud.end());
  }
  // The panorama is an overview drawn by nearest pixel: a stage that turns no view by a quarter
  // of its pixel leaves it as drawn (a bumped tripod's tilt zero turns them by 1.5 pixels).
  const double turn_deg = LargestViewTurnDeg(in->calibration, refined, left_images);
  if (turn_deg > 0.25 * options_.panorama.deg_per_px) {
    PanoramaBuilder panorama(refined, options_.panorama);
    panorama.Add(left_images);
    w->panorama = panorama.Image();
  }
  in->calibration = refined;
  in->calibration_source += " (stage self-calibrated)";
  in->calibration_sha256 = Sha256Hex(CalibrationToYaml(refined));
  std::lock_guard lock(mutex_);
  worker_calibration_sha256_ = in->calibration_sha256;
  return turn_deg;
}

bool StationProcessor::CheckRigStep(StationInputs* in, StationWork* w, StepSummary* s) {
  const std::vector<PairRecord> records = InPairOrder(in->manifest.pairs);
  if (records.size() < 2) {
    s->warnings.push_back("rig not checked: one pair has no seams");
    return true;
  }
  const Result<std::vector<StereoPairImages>> images = LeftImages(*in, records);
  if (!images) return s->message = images.error(), false;
  // Tie points of the pairs the worker did not tie as they came (all of them for a finished
  // station); the calibration is levelled as the station already (station_inputs.h).
  std::vector<StereoPairImages> untied;
  std::vector<MatchedPair> matched;
  std::vector<int> order;
  for (size_t i = 0; i < records.size(); ++i) {
    const PairRecord& p = records[i];
    order.push_back(p.index);
    if (tie_finder_->Has(p.index, p.readback.pan_deg, p.readback.tilt_deg)) continue;
    untied.push_back((*images)[i]);
    matched.push_back(matched_.at(p.index));
  }
  if (!untied.empty()) tie_finder_->Add(untied, matched);
  const Result<RigCheck> check =
      CheckRig({StationTiePoints(tie_finder_->Input(order), records, options_.rig_adjustment)},
               options_.rig_adjustment);
  if (!check) {
    s->warnings.push_back("rig not checked: " + check.error());
    return true;
  }
  const bool used = options_.self_calibrate_rig;
  w->rig_check = RigCheckJson(*check, used);
  w->seams_image = RenderSeamsImage(check->before, check->after);
  s->counts = {{"rig_tie_points", check->tie_points},
               {"pairs_tied_during_capture", records.size() - untied.size()},
               {"seams_within_2_sigma", check->before.within_2_sigma}};
  if (!used) {
    if (!check->SeamsClose())
      s->warnings.push_back("the seams do not close: " + SeamsLine(check->before) +
                            "; the stage has moved since its calibration: process with "
                            "--self-calibrate-rig, or calibrate rig");
    return true;
  }
  if (check->after.within_2_sigma < RigCheck::kClosedShare)
    s->warnings.push_back("the seams do not close after the rig's self-calibration: " +
                          SeamsLine(check->after));
  // The data's share. The held cameras' share is how far their errors move the stage, not the
  // sight lines: where the tilt zero takes up a camera's pitch the two turn the lines back
  // against each other, so it bounds the lines' tilt from above only (flat seed 1: 0.0019 deg
  // against the data's 0.0043).
  w->sight_tilt_sigma_deg = SightTiltSigmaDeg(check->adjustment.SigmaOfTheData());
  Calibration refined = in->calibration;
  refined.stage = check->adjustment.stage;
  s->counts["largest_view_turn_deg"] = MoveToStage(refined, *images, in, w);
  return true;
}

Result<ProcessResult> StationProcessor::Finish() {
  summary_ = {};
  StepRunner run(control_, kStepCount, &summary_);
  std::string why;
  if (!options_.Check(&why)) return Error{"process options: " + why};
  std::optional<StationInputs> inputs;
  StationWork work;
  run.Run("load", [&](StepSummary* s) {
    Result<StationInputs> loaded = LoadStationInputs(
        dir_, options_.calibration_file, options_.gcp_file, options_.set_up_from_calibration_file);
    if (!loaded) return s->message = loaded.error(), false;
    inputs = std::move(*loaded);
    const StationManifest& m = inputs->manifest;
    if (m.pairs.empty()) return s->message = dir_ + "/station.json: pairs: no pair captured", false;
    if (!m.Complete())
      s->warnings.push_back("station incomplete: " + std::to_string(m.pairs.size()) + " of " +
                            std::to_string(m.plan.size()) + " pairs");
    work.inputs = &*inputs;
    return true;
  });
  run.Run("matching", [&](StepSummary* s) { return MatchPairs(&run, &work, s); });
  run.Run("rig", [&](StepSummary* s) { return CheckRigStep(&*inputs, &work, s); });
  for (const auto& [name, step] : kStationSteps)
    run.Run(name, [&, step = step](StepSummary* s) { return step(options_, &work, s); });
  nlohmann::json report;
  run.Run("report", [&](StepSummary* s) {
    report = BuildProcessReport(options_, work, summary_, run.elapsed_s());
    const Status written =
        WriteFileAtomically(dir_ + "/products/report.json", report.dump(2) + "\n");
    if (!written) s->message = written.error();
    return written.ok();
  });
  run.Finish();
  if (!summary_.IsUsable()) return Error{summary_.message};
  ProcessResult result;
  result.report = std::move(report);
  result.summary = summary_;
  result.cloud = std::move(work.cloud);
  result.point_class = std::move(work.point_class);
  result.dem = std::move(work.kriged.dem);
  result.dem_std = std::move(work.kriged.std);
  result.terrain_correction = work.terrain_correction;
  return result;
}

Result<ProcessResult> ProcessStation(const std::string& station_dir, const ProcessOptions& options,
                                     const ProcessControl& control) {
  StationProcessor processor(station_dir, options, control);
  return processor.Finish();
}

}  // namespace ts
