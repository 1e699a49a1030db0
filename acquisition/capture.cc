#include "acquisition/capture.h"

#include "acquisition/pair_sequencer.h"

#include <cmath>
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
  for (const StagePose& pose : given_plan)
    if (!(std::abs(pose.tilt_deg) <= plan.max_abs_tilt_deg) || !std::isfinite(pose.pan_deg)) {
      if (why)
        *why = "a planned pose at tilt " + std::to_string(pose.tilt_deg) +
               " deg passes the stage limit of +-" + std::to_string(plan.max_abs_tilt_deg) + " deg";
      return false;
    }
  return true;
}

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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
    m.plan = o.given_plan.empty() ? MakeCapturePlan(m.calibration, o.plan) : o.given_plan;
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
  p.inclinometer_deg = frames.inclinometer_deg;
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
  PairSequencer seq(left, right, o, progress, &summary);
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
    if (stage.interrupted()) {  // between pairs: nothing half-written, the stage stopped
      if (Status s = stage.Stop(); !s) return Error{s.error()};
      return Error{std::string("capture ") + Stage::kInterruptedMessage + " before " +
                   PairName(index)};
    }
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
    // An inclinometer on the pan platform, read at every pose, tells the levelling from its
    // own index error (inclinometer.h); one on the base has nothing new to say. A failed read
    // costs only that reading.
    if (rig.stage.inclinometer_turns_with_pan) {
      if (const Result<StageInfo> tilt = stage.Identify(); tilt)
        frames->inclinometer_deg =
            Eigen::Vector2d(tilt->inclinometer_x_deg, tilt->inclinometer_y_deg);
      else
        Log().info("{}: inclinometer not read: {}", PairName(index), tilt.error());
    }
    // Terrain going on above this view: the pose above it is taken next. The plan grows in
    // memory and is saved with this pair's commit, so a resume knows it.
    const auto look_up_started = Clock::now();
    const bool upper =
        o.given_plan.empty() &&
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
