#include "acquisition/capture.h"

#include <filesystem>
#include <optional>

#include "core/log.h"
#include "core/seconds.h"
#include "processing/io/atomic_file.h"
#include "processing/io/station_manifest.h"
#include "processing/io/station_validator.h"
#include "processing/matching/terrain_above_view.h"

namespace ts {

bool CaptureOptions::Check(std::string* why) const {
  if (!CheckDeclaredOptions(*this, why)) return false;
  std::string err;
  if (!plan.Check(&err) || !exposure.Check(&err)) {
    if (why) *why = err;
    return false;
  }
  return true;
}

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string PairName(int index) {
  char name[16];
  std::snprintf(name, sizeof(name), "pair %02d", index);
  return name;
}

// Removes what a stopped writer may have left: temporary files, and images of pairs the
// manifest never committed (they are taken again).
void CleanRaw(const std::string& dir, const StationManifest& m) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "raw", ec)) {
    const std::string name = entry.path().filename().string();
    const std::string relative = "raw/" + name;
    bool committed = false;
    for (const PairRecord& p : m.pairs)
      committed |= p.left.file == relative || p.right.file == relative;
    if (IsTemporaryName(name) || !committed) fs::remove(entry.path(), ec);
  }
}

Result<StationManifest> NewStation(const RigConfig& rig, const StageInfo& info,
                                   const std::string& dir, const CaptureOptions& o) {
  if (fs::exists(fs::path(dir) / kManifestFileName))
    return Error{dir + ": already holds a station (station.json); use --resume to complete it"};
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "raw", ec);
  if (ec) return Error{dir + ": cannot create station directory: " + ec.message()};
  StationManifest m;
  m.station_id = fs::path(dir).filename().string();
  m.software_version = "topostation capture";
  m.rig_name = rig.name;
  m.calibration = rig.calibration;
  // The levelling is measured now, by the stage's inclinometer.
  m.calibration.stage.levelling_x_deg = info.inclinometer_x_deg;
  m.calibration.stage.levelling_y_deg = info.inclinometer_y_deg;
  m.image_width_px = rig.calibration.rig.left.width_px;
  m.image_height_px = rig.calibration.rig.left.height_px;
  m.pixel_format = o.format;
  try {
    m.plan = MakeCapturePlan(m.calibration, o.plan);
  } catch (const std::invalid_argument& e) {
    return Error{rig.file + ": " + e.what()};
  }
  if (Status s = SaveStationManifest(&m, dir); !s) return Error{s.error()};
  return m;
}

Result<StationManifest> ResumeStation(const std::string& dir) {
  if (!fs::exists(fs::path(dir) / kManifestFileName))
    return Error{dir + ": no station.json to resume"};
  Result<StationManifest> m = LoadStationManifest(dir);
  if (!m) return m;
  // Keep only pairs whose images are intact; the others are taken again.
  std::vector<PairRecord> intact;
  for (const PairRecord& p : m->pairs)
    if (CheckPairImages(dir, *m, p, PairName(p.index))) intact.push_back(p);
  m->pairs = intact;
  CleanRaw(dir, *m);
  if (Status s = SaveStationManifest(&*m, dir); !s) return Error{s.error()};
  return m;
}

struct PairFrames {
  Frame left, right;
  StagePose readback;
};

class Sequencer {
 public:
  Sequencer(Camera& left, Camera& right, const CaptureOptions& o,
            const std::function<void(const CaptureEvent&)>& progress, CaptureSummary* summary)
      : left_(left), right_(right), o_(o), progress_(progress), summary_(summary) {}

  double exposure_us = 0.0;
  PairTimeline timeline;  // of the pair being taken

  // Both frames of one trigger, retried (and the cameras reconnected) on a lost frame.
  Result<std::pair<Frame, Frame>> GrabBoth(int index) {
    std::string last_error;
    int failures[2] = {0, 0};
    for (int attempt = 0; attempt < o_.frame_attempts; ++attempt) {
      if (attempt > 0) ++summary_->frame_retries;
      // Each camera answers for itself: a trigger the right camera missed says nothing about
      // the left one (whose frame, if any, is waited for and dropped with the pair).
      const auto triggered = Clock::now();
      const Status tl = left_.Trigger();
      const Status tr = right_.Trigger();
      Result<Frame> l = tl ? left_.WaitFrame(o_.frame_timeout) : Result<Frame>(Error{tl.error()});
      Result<Frame> r = tr ? right_.WaitFrame(o_.frame_timeout) : Result<Frame>(Error{tr.error()});
      timeline.trigger_to_frame_s += Seconds(Clock::now() - triggered);
      ++timeline.triggers;
      if (l && r) {
        const uint64_t resent = l->statistics.resent_packets + r->statistics.resent_packets;
        if (resent > 0) Log().info("{}: {} GVSP packets lost and resent", PairName(index), resent);
        summary_->resent_packets += resent;
        return std::pair{std::move(*l), std::move(*r)};
      }
      last_error = !l ? l.error() : r.error();
      Emit({CaptureEventKind::kFrameRetry, index, 0, last_error});
      // A camera that lost its control channel, or failed twice, is opened again.
      for (int i = 0; i < 2; ++i) {
        Camera& c = i == 0 ? left_ : right_;
        if (i == 0 ? l.ok() : r.ok()) continue;
        if (!c.ControlLost() && ++failures[i] < 2) continue;
        if (Status s = c.Reconnect(o_.reconnect_budget); !s)
          return Error{c.Describe() + " lost at " + PairName(index) + ": " + last_error +
                       "; reconnecting failed: " + s.error()};
        if (Status s = c.SetExposure(exposure_us, o_.gain_db); !s) return Error{s.error()};
      }
    }
    return Error{"no complete frame pair at " + PairName(index) + " after " +
                 std::to_string(o_.frame_attempts) + " triggers: " + last_error};
  }

  // A pair that passes the exposure check, retaken with a corrected exposure if needed.
  Result<PairFrames> TakePair(int index, int total) {
    for (int retake = 0;; ++retake) {
      Result<std::pair<Frame, Frame>> frames = GrabBoth(index);
      if (!frames) return Error{frames.error()};
      const auto judged = Clock::now();
      const ExposureVerdict v =
          JudgeExposure(frames->first.image, frames->second.image, exposure_us, o_.exposure);
      timeline.verify_s += Seconds(Clock::now() - judged);
      if (v.ok || retake >= o_.max_retakes)
        return PairFrames{std::move(frames->first), std::move(frames->second), {}};
      ++summary_->retakes;
      Emit({CaptureEventKind::kRetake, index, total,
            v.reason + ": exposure " + std::to_string(exposure_us) + " -> " +
                std::to_string(v.next_exposure_us) + " us"});
      exposure_us = v.next_exposure_us;
      for (Camera* c : {&left_, &right_})
        if (Status s = c->SetExposure(exposure_us, o_.gain_db); !s) return Error{s.error()};
    }
  }

  void Emit(const CaptureEvent& e) {
    if (e.kind == CaptureEventKind::kRetake)
      Log().info("{} retaken: {}", PairName(e.pair), e.message);
    if (e.kind == CaptureEventKind::kFrameRetry)
      Log().warn("{} triggered again: {}", PairName(e.pair), e.message);
    if (e.kind == CaptureEventKind::kUpperPose) Log().info("{}: {}", PairName(e.pair), e.message);
    if (progress_) progress_(e);
  }

 private:
  Camera& left_;
  Camera& right_;
  const CaptureOptions& o_;
  const std::function<void(const CaptureEvent&)>& progress_;
  CaptureSummary* summary_;
};

// Writes both images, then commits the pair with its timeline (write_s and pair_s added here;
// pair_s counts from pair_started).
Status CommitPair(const std::string& dir, int index, const StagePose& commanded,
                  const PairFrames& frames, double exposure_us, double gain_db,
                  const PairTimeline& timeline, Clock::time_point pair_started,
                  StationManifest* m) {
  const auto write_started = Clock::now();
  PairRecord p;
  p.index = index;
  p.commanded = commanded;
  p.readback = frames.readback;
  p.exposure_us = exposure_us;
  p.gain_db = gain_db;
  p.captured_utc = UtcNowIso8601();
  p.left_timestamp_ns = frames.left.timestamp_ns;
  p.right_timestamp_ns = frames.right.timestamp_ns;
  for (Side side : {Side::kLeft, Side::kRight}) {
    ImageRecord& record = side == Side::kLeft ? p.left : p.right;
    record.file = StationManifest::ImageFileName(index, side);
    const cv::Mat& image = side == Side::kLeft ? frames.left.image : frames.right.image;
    if (image.cols != m->image_width_px || image.rows != m->image_height_px)
      return Error{std::string(SideName(side)) + " image of " + PairName(index) + " is " +
                   std::to_string(image.cols) + "x" + std::to_string(image.rows) + ", expected " +
                   std::to_string(m->image_width_px) + "x" + std::to_string(m->image_height_px)};
    const Result<std::string> sha =
        WritePngAtomically(image, (fs::path(dir) / record.file).string());
    if (!sha) return Error{sha.error()};
    record.sha256 = *sha;
  }
  p.timeline = timeline;
  p.timeline.write_s = Seconds(Clock::now() - write_started);
  p.timeline.pair_s = Seconds(Clock::now() - pair_started);
  m->pairs.push_back(p);
  return SaveStationManifest(m, dir);  // the commit
}

}  // namespace

Result<CaptureSummary> CaptureStation(Stage& stage, Camera& left, Camera& right,
                                      const RigConfig& rig, const std::string& dir, bool resume,
                                      const CaptureOptions& o,
                                      const std::function<void(const CaptureEvent&)>& progress) {
  const auto t0 = Clock::now();
  std::string why;
  if (!o.Check(&why)) return Error{"capture: " + why};
  const Result<StageInfo> info = stage.Identify();
  if (!info) return Error{info.error()};
  Result<StationManifest> m = resume ? ResumeStation(dir) : NewStation(rig, *info, dir, o);
  if (!m) return Error{m.error()};

  CaptureSummary summary;
  summary.total_pairs = static_cast<int>(m->plan.size());
  summary.already_present = static_cast<int>(m->pairs.size());
  std::vector<int> missing;
  for (int i = 0; i < summary.total_pairs; ++i)
    if (!m->FindPair(i)) missing.push_back(i);
  Sequencer seq(left, right, o, progress, &summary);
  seq.exposure_us = m->pairs.empty() ? o.initial_exposure_us : m->pairs.back().exposure_us;
  seq.Emit({CaptureEventKind::kStarted, -1, summary.total_pairs,
            std::to_string(missing.size()) + " of " + std::to_string(summary.total_pairs) +
                " pairs to capture"});
  if (missing.empty()) {
    summary.seconds = Seconds(Clock::now() - t0);
    return summary;
  }

  CameraSettings settings;
  settings.width_px = m->image_width_px;
  settings.height_px = m->image_height_px;
  settings.format = m->pixel_format;
  settings.exposure_us = seq.exposure_us;
  settings.gain_db = o.gain_db;
  for (Camera* c : {&left, &right}) {
    settings.packet_size_bytes =
        (c == &left ? rig.left_camera : rig.right_camera).packet_size_bytes;
    if (Status s = c->Configure(settings); !s) return Error{s.error()};
    if (Status s = c->Start(); !s) return Error{s.error()};
  }
  const Result<AxisState> pan = stage.ReadAxis(Axis::kPan);
  const Result<AxisState> tilt = stage.ReadAxis(Axis::kTilt);
  if (!pan || !tilt) return Error{!pan ? pan.error() : tilt.error()};
  if (!pan->homed() || !tilt->homed())
    if (Status s = stage.Home(o.home_timeout); !s) return Error{s.error()};

  const Rectification rectification = Rectify(m->calibration.rig);  // for the upper poses
  if (Status s = stage.StartMove(m->plan[missing[0]]); !s) return Error{s.error()};
  Clock::time_point pair_started = Clock::now();
  for (size_t k = 0; k < missing.size(); ++k) {
    const int index = missing[k];
    seq.Emit({CaptureEventKind::kMoving, index, summary.total_pairs, "",
              summary.already_present + summary.captured_now});
    seq.timeline = {};
    seq.timeline.trigger_to_frame_s = seq.timeline.verify_s = 0.0;
    const auto wait_started = Clock::now();
    const Result<StagePose> at = stage.WaitInPosition(o.position_tolerance_deg, o.move_timeout);
    if (!at) return Error{at.error() + " (moving to " + PairName(index) + ")"};
    seq.timeline.stage_wait_s = Seconds(Clock::now() - wait_started);
    const MoveTiming move = stage.last_move_timing();
    seq.timeline.move_s = move.moving_s;
    seq.timeline.settle_s = move.settling_s;
    Result<PairFrames> frames = seq.TakePair(index, summary.total_pairs);
    if (!frames) return Error{frames.error()};
    frames->readback = *at;
    // Terrain going on above this view: the pose above it is taken next. The plan grows in
    // memory and is saved with this pair's commit, so a resume knows it.
    const auto look_up_started = Clock::now();
    const bool upper =
        ExtendPlanUpwards(m->calibration, rectification, frames->left.image, frames->right.image,
                          m->plan[index], *at, o.plan, &m->plan);
    seq.timeline.verify_s += Seconds(Clock::now() - look_up_started);
    if (upper) {
      missing.insert(missing.begin() + static_cast<long>(k) + 1,
                     static_cast<int>(m->plan.size()) - 1);
      summary.total_pairs = static_cast<int>(m->plan.size());
      seq.Emit({CaptureEventKind::kUpperPose, index, summary.total_pairs,
                "terrain goes on above the view: a pose higher up at tilt " +
                    std::to_string(m->plan.back().tilt_deg) + " deg"});
    }
    if (k + 1 < missing.size())  // the stage moves on while this pair is written
      if (Status s = stage.StartMove(m->plan[missing[k + 1]]); !s) return Error{s.error()};
    if (Status s = CommitPair(dir, index, m->plan[index], *frames, seq.exposure_us, o.gain_db,
                              seq.timeline, pair_started, &*m);
        !s)
      return Error{s.error()};
    pair_started = Clock::now();
    ++summary.captured_now;
    seq.Emit({CaptureEventKind::kPairCaptured, index, summary.total_pairs, "",
              summary.already_present + summary.captured_now, &m->pairs.back(), &frames->left.image,
              &frames->right.image});
  }
  for (Camera* c : {&left, &right})
    if (Status s = c->Stop(); !s) return Error{s.error()};
  summary.exposure_us = seq.exposure_us;
  summary.timeline = CaptureTimelineJson(
      std::vector<PairRecord>(m->pairs.end() - summary.captured_now, m->pairs.end()));
  summary.seconds = Seconds(Clock::now() - t0);
  seq.Emit({CaptureEventKind::kFinished, -1, summary.total_pairs, ""});
  return summary;
}

}  // namespace ts
