#include "station/daemon/job_runner.h"

#include <filesystem>

#include "acquisition/capture.h"
#include "acquisition/retake.h"
#include "core/log.h"
#include "devices/aravis_camera.h"
#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/station_manifest.h"
#include "processing/pipeline/process_station.h"
#include "station/daemon/calibrate_job.h"

namespace ts::daemon {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The tail of a survey after its last pair (the station-wide steps), for the time left.
constexpr double kProductsAfterLastPairS = 4.0;

double SecondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// What the history keeps of a processing run: the terrain correction and its verdict.
nlohmann::json ProcessSummaryJson(const nlohmann::json& report) {
  nlohmann::json s;
  for (const char* key : {"terrain_correction_mgal", "terrain_correction_sigma_mgal", "verdict",
                          "unusable_because", "warnings", "wall_s"})
    if (report.contains(key)) s[key] = report[key];
  return s;
}

// A rig job's capture: the panorama (a survey's single row when asked), exactly the poses a
// retake names, or a control field's grid of stage poses.
CaptureOptions CaptureOptionsFor(const Job& job) {
  CaptureOptions options;
  options.plan.upper_poses =
      !job.parameters.value("single_row", false) && job.kind != JobKind::kRetake;
  if (job.kind != JobKind::kCaptureField) return options;
  FieldPoseGrid grid;
  grid.centre_pan_deg = job.parameters.value("field_pan_deg", 0.0);
  grid.centre_tilt_deg = job.parameters.value("field_tilt_deg", 0.0);
  grid.pans = job.parameters.value("field_pans", grid.pans);
  grid.tilts = job.parameters.value("field_tilts", grid.tilts);
  options.given_plan = MakeFieldPoseGrid(grid);
  options.plan.upper_poses = false;
  return options;
}

std::vector<StagePose> RetakePoses(const Job& job) {
  std::vector<StagePose> poses;
  for (const nlohmann::json& p : job.parameters.value("poses", nlohmann::json::array()))
    poses.push_back({p.value("pan_deg", 0.0), p.value("tilt_deg", 0.0)});
  return poses;
}

// A field session's cameras to start from (the rig's now) beside it, and the command that
// follows once a person has marked four targets.
Status FinishFieldSession(const Calibration& rig, const std::string& dir, nlohmann::json* summary) {
  (*summary)["session"] = dir;
  (*summary)["next"] = "mark 4 or more targets, then a calibrate_field job with session '" +
                       fs::path(dir).filename().string() +
                       "', the control field and the marks; or, with FIELD.yaml and MARKS.yaml, "
                       "topostation calibrate stereo --left '" +
                       dir + "/raw/*_left.png' --right '" + dir +
                       "/raw/*_right.png' --control-field FIELD.yaml --marks MARKS.yaml --start " +
                       dir + "/design.yaml --stage-from " + dir + "/design.yaml --out CAL.yaml";
  return SaveCalibrationYaml(rig, dir + "/design.yaml");
}

ProcessOptions DaemonProcessOptions() {
  ProcessOptions o;
  o.self_calibrate_rig = true;  // the stage drifts with every transport (issue 21)
  return o;
}

}  // namespace

struct JobRunner::Running {
  Job job;
  std::unique_ptr<RigLease> lease;
  std::atomic<bool> cancel{false};
  Clock::time_point started = Clock::now();
  Clock::time_point first_pair{};
  int pairs_done_now = 0;
  nlohmann::json progress;  // guarded by JobRunner::mutex_
  cv::Mat last_left, last_right;
};

JobRunner::JobRunner(const DaemonConfig& config, JobStore* store, DeviceSupervisor* devices,
                     EventHub* events)
    : config_(config), store_(store), devices_(devices), events_(events) {
  std::error_code ec;
  fs::create_directories(config_.stations_dir, ec);
  process_thread_ = std::thread([this] { ProcessLoop(); });
}

JobRunner::~JobRunner() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
    if (rig_job_) rig_job_->cancel = true;
    cancel_processing_ = true;
    process_wake_.notify_all();
  }
  if (Status s = devices_->StopStage(); !s) Log().warn("stopping the stage: {}", s.error());
  if (rig_thread_.joinable()) rig_thread_.join();
  process_thread_.join();
}

std::string JobRunner::StationDir(const std::string& station) const {
  return (fs::path(config_.stations_dir) / station).string();  // station passed IsStationId
}

std::string JobRunner::DirOf(const Job& job) const {
  // A calibration session, not a station: what capture_field takes and calibrate_field reads.
  if (job.kind == JobKind::kCaptureField || job.kind == JobKind::kCalibrateField)
    return (fs::path(config_.state_dir) / "calibration-sessions" / job.station).string();
  return StationDir(job.station);
}

void JobRunner::PublishJob(int64_t id) {
  if (Result<Job> job = store_->Get(id)) events_->Publish("job", job->ToJson());
}

void JobRunner::SetState(Running* run, JobState state, const nlohmann::json& summary,
                         const std::string& error) {
  {
    std::lock_guard lock(mutex_);  // CurrentJob() reads it from the API's threads
    run->job.state = state;
  }
  Record(run->job.id, state, summary, error);
}

void JobRunner::Record(int64_t id, JobState state, const nlohmann::json& summary,
                       const std::string& error) {
  if (Status s = store_->SetState(id, state, summary, error); !s) Log().error("{}", s.error());
  PublishJob(id);
}

std::variant<Job, JobError> JobRunner::Submit(const JobRequest& request,
                                              const std::string& idempotency_key, bool* existed) {
  *existed = false;
  if (!idempotency_key.empty())  // a request sent again: its job, whatever it became
    if (std::optional<Job> earlier = store_->FindByKey(idempotency_key)) {
      *existed = true;
      return *earlier;
    }
  Job job;
  job.kind = request.kind;
  job.station = request.station;
  job.parameters = request.fields;
  job.idempotency_key = idempotency_key;
  const bool station_exists = fs::exists(fs::path(DirOf(job)) / kManifestFileName);
  if (!UsesRig(request.kind)) {
    if (request.kind == JobKind::kCalibrateField) {
      if (!station_exists)
        return JobError{
            404, "no calibration session '" + request.station + "': a capture_field job takes one"};
    } else {
      for (const std::string& s :
           request.stations.empty() ? std::vector{request.station} : request.stations)
        if (!fs::exists(fs::path(StationDir(s)) / kManifestFileName))
          return JobError{404, "no station '" + s + "'"};
    }
    Result<Job> created = store_->Create(job, existed);
    if (!created) return JobError{500, created.error()};
    std::lock_guard lock(mutex_);
    process_queue_.push_back(created->id);
    process_wake_.notify_all();
    events_->Publish("job", created->ToJson());
    return *created;
  }
  if (request.kind == JobKind::kRetake && !station_exists)
    return JobError{404, "no station '" + request.station + "' to retake poses of"};
  if (station_exists && request.kind != JobKind::kRetake)
    return JobError{409, "station '" + request.station +
                             "' exists already: choose another id, or resume the job that "
                             "captured it"};
  auto lease = LeaseRig(request.kind, request.station);
  if (const JobError* e = std::get_if<JobError>(&lease)) return *e;
  Result<Job> created = store_->Create(job, existed);
  if (!created) return JobError{500, created.error()};
  StartRigJob(*created, std::move(std::get<std::unique_ptr<RigLease>>(lease)));
  return *created;
}

std::variant<Job, JobError> JobRunner::Resume(int64_t id) {
  Result<Job> job = store_->Get(id);
  if (!job) return JobError{404, job.error()};
  if (!UsesRig(job->kind) ||
      !(job->state == JobState::kInterrupted || job->state == JobState::kFailed ||
        job->state == JobState::kCancelled))
    return JobError{409, "job " + std::to_string(id) + " is a " + JobKindName(job->kind) +
                             " job in state " + JobStateName(job->state) +
                             ": only a stopped survey or capture resumes"};
  auto lease = LeaseRig(job->kind, job->station);
  if (const JobError* e = std::get_if<JobError>(&lease)) return *e;
  job->parameters["resumed"] = job->parameters.value("resumed", 0) + 1;
  if (Status s = store_->SetParameters(id, job->parameters); !s) return JobError{500, s.error()};
  Record(id, JobState::kQueued);
  job->state = JobState::kQueued;
  StartRigJob(*job, std::move(std::get<std::unique_ptr<RigLease>>(lease)));
  return *job;
}

std::variant<Job, JobError> JobRunner::Cancel(int64_t id) {
  Result<Job> job = store_->Get(id);
  if (!job) return JobError{404, job.error()};
  {
    std::lock_guard lock(mutex_);
    if (rig_job_ && rig_job_->job.id == id) {
      rig_job_->cancel = true;
    } else if (processing_id_ == id) {
      cancel_processing_ = true;
    } else if (auto it = std::find(process_queue_.begin(), process_queue_.end(), id);
               it != process_queue_.end()) {
      process_queue_.erase(it);
      Record(id, JobState::kCancelled, nullptr, "cancelled before it started");
      return *store_->Get(id);
    } else {
      return JobError{409, "job " + std::to_string(id) + " is " + JobStateName(job->state) +
                               ": nothing runs to cancel"};
    }
  }
  if (UsesRig(job->kind))  // at once, not at the next pair
    if (Status s = devices_->StopStage(); !s) Log().warn("stopping the stage: {}", s.error());
  return *store_->Get(id);
}

std::variant<std::unique_ptr<RigLease>, JobError> JobRunner::LeaseRig(JobKind kind,
                                                                      const std::string& station) {
  std::string holder;
  std::unique_ptr<RigLease> lease =
      devices_->TryLease(std::string(JobKindName(kind)) + " of station " + station, &holder);
  if (!lease) return JobError{409, "the rig is in use: " + holder};
  if (const std::string why = devices_->WhyNotReady(); !why.empty())
    return JobError{409, "the rig cannot capture: " + why};
  return lease;
}

void JobRunner::StartRigJob(const Job& job, std::unique_ptr<RigLease> lease) {
  std::lock_guard lock(mutex_);
  if (rig_thread_.joinable()) rig_thread_.join();  // the last rig job has returned its lease
  rig_job_ = std::make_unique<Running>();
  rig_job_->job = job;
  rig_job_->lease = std::move(lease);
  rig_thread_ = std::thread([this, run = rig_job_.get()] { RunRigJob(run); });
}

nlohmann::json JobRunner::CurrentJob() const {
  std::lock_guard lock(mutex_);
  // A rig job that has ended but not yet given the rig back is no longer current.
  if (!rig_job_ || IsFinal(rig_job_->job.state)) {
    if (processing_id_ == 0) return nullptr;
    Result<Job> job = store_->Get(processing_id_);
    if (!job) return nullptr;
    return {{"id", job->id},
            {"kind", JobKindName(job->kind)},
            {"station", job->station},
            {"state", JobStateName(job->state)}};
  }
  nlohmann::json j = rig_job_->progress;
  j["id"] = rig_job_->job.id;
  j["kind"] = JobKindName(rig_job_->job.kind);
  j["station"] = rig_job_->job.station;
  j["state"] = JobStateName(rig_job_->job.state);
  return j;
}

cv::Mat JobRunner::LastFrame(Side side) const {
  std::lock_guard lock(mutex_);
  if (!rig_job_) return {};
  return side == Side::kLeft ? rig_job_->last_left : rig_job_->last_right;
}

void JobRunner::RunRigJob(Running* run) {
  const Job& job = run->job;
  const std::string dir = DirOf(job);
  // A retake ends as a survey does: the station processed with every pair.
  const bool survey = job.kind == JobKind::kSurvey || job.kind == JobKind::kRetake;
  auto fail = [&](const std::string& error) {
    Log().warn("job {} ({} of {}): {}", job.id, JobKindName(job.kind), job.station, error);
    if (quit_ && run->job.state == JobState::kProcessing) return;  // runs again at the next start
    const std::string kept = " (the pairs taken are kept; resuming the job completes the station)";
    if (quit_)
      SetState(run, JobState::kInterrupted, nullptr, "the daemon stopped: " + error + kept);
    else if (run->cancel)
      SetState(run, JobState::kCancelled, nullptr, "cancelled: " + error + kept);
    else
      SetState(run, JobState::kFailed, nullptr, error);
  };
  auto body = [&]() -> void {
    Result<RigConfig> rig = LoadRigConfig(config_.rig_file);  // a new calibration applies now
    if (!rig) return fail(rig.error());
    // A calibration session tapes no height (0): the stage's origin stands for its mark.
    const double taped = job.parameters.value("instrument_height_m", 0.0);
    rig->calibration.stage.height_above_mark_m = 0.0;
    if (taped > 0.0)
      if (Status s = rig->calibration.stage.SetInstrumentHeight(taped); !s)
        return fail("instrument_height_m: " + s.error());
    const bool resume = fs::exists(fs::path(dir) / kManifestFileName);
    if (job.kind == JobKind::kRetake) {
      if (!resume) return fail("station " + job.station + " has no capture to retake from");
      Result<RetakeSummary> aside = SetPairsAsideForRetake(dir, RetakePoses(job));
      if (!aside) return fail(aside.error());
      Log().info("retake of {}: {} pairs set aside in {}, {} poses added", job.station,
                 aside->set_aside, aside->folder, aside->added);
    } else if (!resume) {
      std::error_code ec;
      fs::create_directories(dir, ec);
      nlohmann::json fields = job.parameters;
      fields["station"] = job.station;
      fields["job"] = job.id;
      if (Status s = WriteFileAtomically(dir + "/station_fields.json", fields.dump(2) + "\n"); !s)
        return fail(s.error());
    }
    SetState(run, JobState::kCapturing);
    Result<Stage*> stage = run->lease->stage();
    if (!stage) return fail(stage.error());
    auto left = OpenAravisCamera(rig->left_camera);
    if (!left) return fail(left.error());
    auto right = OpenAravisCamera(rig->right_camera);
    if (!right) return fail(right.error());

    ProcessControl control;
    control.should_stop = [run] { return run->cancel.load(); };
    control.progress = [this, run](const ProcessProgress& p) {
      std::lock_guard lock(mutex_);
      run->progress["step"] = p.step;
      run->progress["step_number"] = p.step_number;
      run->progress["step_count"] = p.step_count;
      if (p.pairs_total > 0) run->progress["pairs_matched"] = p.pairs_done;
    };
    std::unique_ptr<StationProcessor> processor;
    if (survey)
      processor = std::make_unique<StationProcessor>(dir, DaemonProcessOptions(), control);
    const Result<CaptureSummary> captured =
        CaptureStation(**stage, **left, **right, *rig, dir, resume, CaptureOptionsFor(job),
                       [&](const CaptureEvent& e) {
                         OnCaptureEvent(run, e);
                         if (processor && e.kind == CaptureEventKind::kPairCaptured)
                           processor->AddPair(*e.record, *e.left_image, *e.right_image);
                       });
    if (!captured) return fail(captured.error());
    nlohmann::json summary = {{"pairs", captured->total_pairs},
                              {"captured_now", captured->captured_now},
                              {"capture_s", captured->seconds},
                              {"retakes", captured->retakes},
                              {"frame_retries", captured->frame_retries}};
    if (job.kind == JobKind::kCaptureField)
      if (Status s = FinishFieldSession(rig->calibration, dir, &summary); !s)
        return fail(s.error());
    if (!survey) return SetState(run, JobState::kDone, summary);
    SetState(run, JobState::kProcessing);
    Result<ProcessResult> processed = processor->Finish();
    if (!processed) return fail(processed.error());
    summary.update(ProcessSummaryJson(processed->report));
    SetState(run, JobState::kDone, summary);
  };
  body();
  std::lock_guard lock(mutex_);
  rig_job_.reset();  // returns the rig to the supervisor
}

void JobRunner::OnCaptureEvent(Running* run, const CaptureEvent& e) {
  std::lock_guard lock(mutex_);
  nlohmann::json& p = run->progress;
  p["phase"] = "capture";
  p["pairs_total"] = e.total;
  if (e.kind == CaptureEventKind::kMoving) p["pair"] = e.pair, p.erase("message");
  if (e.kind == CaptureEventKind::kPairCaptured) {
    p["pairs_done"] = e.captured;
    if (run->pairs_done_now++ == 0) run->first_pair = Clock::now();
    p["pan_deg"] = e.record->readback.pan_deg;  // the stage as the pair was taken
    p["tilt_deg"] = e.record->readback.tilt_deg;
    p["exposure_us"] = e.record->exposure_us;
    run->last_left = *e.left_image;  // shared, never modified (CaptureEvent)
    run->last_right = *e.right_image;
  }
  p["elapsed_s"] = SecondsSince(run->started);
  const int left_to_take = e.total - p.value("pairs_done", 0);
  if (run->pairs_done_now >= 2) {
    const double per_pair = SecondsSince(run->first_pair) / (run->pairs_done_now - 1);
    p["time_left_s"] = per_pair * left_to_take +
                       (run->job.kind == JobKind::kSurvey ? kProductsAfterLastPairS : 0.0);
  }
  if (!e.message.empty()) p["message"] = e.message;
  nlohmann::json event = p;
  event["id"] = run->job.id;
  event["station"] = run->job.station;
  event["state"] = JobStateName(run->job.state);
  events_->PublishThrottled("job-progress", "progress", std::move(event));
}

void JobRunner::RecoverAfterRestart() {
  for (const Job& job : store_->RecoverAfterRestart()) {
    const bool captured = fs::exists(fs::path(DirOf(job)) / kManifestFileName);
    if (!UsesRig(job.kind) || captured) {  // a survey that had reached processing, or process
      std::lock_guard lock(mutex_);
      process_queue_.push_back(job.id);
      process_wake_.notify_all();
      continue;
    }
    auto lease = LeaseRig(job.kind, job.station);
    if (const JobError* e = std::get_if<JobError>(&lease))
      Record(job.id, JobState::kInterrupted, nullptr, e->message);
    else
      StartRigJob(job, std::move(std::get<std::unique_ptr<RigLease>>(lease)));
  }
}

void JobRunner::ProcessLoop() {
  std::unique_lock lock(mutex_);
  while (true) {
    process_wake_.wait(lock, [&] { return quit_ || !process_queue_.empty(); });
    if (quit_) return;
    processing_id_ = process_queue_.front();
    process_queue_.pop_front();
    cancel_processing_ = false;
    lock.unlock();
    if (Result<Job> job = store_->Get(processing_id_)) RunProcessJob(*job);
    lock.lock();
    processing_id_ = 0;
  }
}

void JobRunner::RunCalibrateJob(const Job& job) {
  Record(job.id, JobState::kProcessing);
  std::vector<std::string> dirs;
  for (const auto& id : job.parameters["stations"]) dirs.push_back(StationDir(id));
  const Result<RigConfig> rig = LoadRigConfig(config_.rig_file);
  if (!rig) return Record(job.id, JobState::kFailed, nullptr, rig.error());
  const std::string out =
      config_.state_dir + "/calibrations/rig-job-" + std::to_string(job.id) + ".yaml";
  const bool refine_cameras = job.parameters.value("refine_cameras", false);
  Result<nlohmann::json> report = CalibrateRigInChild(dirs, rig->calibration, refine_cameras, out,
                                                      [this] { return cancel_processing_.load(); });
  FinishCalibrateJob(job, out, std::move(report));
}

void JobRunner::RunCalibrateFieldJob(const Job& job) {
  Record(job.id, JobState::kProcessing);
  // Read as the request was checked (ParseCalibrateField): a job recovered after a restart too.
  const Result<ControlField> field = ControlFieldOf(job.parameters);
  const Result<std::vector<ImageMarks>> marks = TargetMarksOf(job.parameters);
  if (!field || !marks)
    return Record(job.id, JobState::kFailed, nullptr, !field ? field.error() : marks.error());
  const std::string out =
      config_.state_dir + "/calibrations/field-job-" + std::to_string(job.id) + ".yaml";
  Result<nlohmann::json> report = CalibrateFieldInChild(
      DirOf(job), job.id, *field, *marks, out, [this] { return cancel_processing_.load(); });
  FinishCalibrateJob(job, out, std::move(report));
}

void JobRunner::FinishCalibrateJob(const Job& job, const std::string& out,
                                   Result<nlohmann::json> report) {
  if (report) {
    (*report)["calibration_file"] = out;
    Record(job.id, JobState::kDone, *report);
  } else if (!quit_) {
    Record(job.id, cancel_processing_ ? JobState::kCancelled : JobState::kFailed, nullptr,
           report.error());
  }
}

void JobRunner::RunProcessJob(const Job& job) {
  if (job.kind == JobKind::kCalibrateRig) return RunCalibrateJob(job);
  if (job.kind == JobKind::kCalibrateField) return RunCalibrateFieldJob(job);
  Record(job.id, JobState::kProcessing);
  ProcessControl control;
  control.should_stop = [this] { return cancel_processing_.load(); };
  control.progress = [this, &job](const ProcessProgress& p) {
    events_->PublishThrottled("process-progress", "progress",
                              {{"id", job.id},
                               {"station", job.station},
                               {"state", "processing"},
                               {"phase", "process"},
                               {"step", p.step},
                               {"step_number", p.step_number},
                               {"step_count", p.step_count},
                               {"elapsed_s", p.elapsed_s}});
  };
  Result<ProcessResult> r =
      ProcessStation(StationDir(job.station), DaemonProcessOptions(), control);
  if (r)
    Record(job.id, JobState::kDone, ProcessSummaryJson(r->report));
  else if (!quit_)  // else left "processing": it runs again at the next start
    Record(job.id, cancel_processing_ ? JobState::kCancelled : JobState::kFailed, nullptr,
           r.error());
}

}  // namespace ts::daemon
