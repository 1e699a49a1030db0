#pragma once
// Runs the daemon's jobs. A rig job (survey, capture) takes the rig from the supervisor when
// it is submitted, so a second one is refused at once with the reason (409); it runs on a
// thread of its own. Process and calibrate_rig jobs queue and run one after another on the
// processing thread.
// A survey matches each pair as it is committed and makes the products after the last.
// Every state change goes to the job history first, then to the events.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <variant>

#include "acquisition/capture.h"
#include "core/result.h"
#include "station/daemon/daemon_config.h"
#include "station/daemon/device_supervisor.h"
#include "station/daemon/event_hub.h"
#include "station/daemon/job_request.h"
#include "station/daemon/job_store.h"

namespace ts::daemon {

// An error with the HTTP status the API answers it with.
struct JobError {
  int http_status = 400;
  std::string message;
};

class JobRunner {
 public:
  JobRunner(const DaemonConfig& config, JobStore* store, DeviceSupervisor* devices,
            EventHub* events);
  ~JobRunner();  // cancels what runs and joins

  // Queues (process) or starts (rig) the job. `*existed`: the key named a job already.
  std::variant<Job, JobError> Submit(const JobRequest& request, const std::string& idempotency_key,
                                     bool* existed);
  // An interrupted, failed or cancelled rig job captures its missing pairs (and a survey
  // then processes); the same job id.
  std::variant<Job, JobError> Resume(int64_t id);
  std::variant<Job, JobError> Cancel(int64_t id);
  // The jobs the last daemon left (JobStore::RecoverAfterRestart), run again.
  void RecoverAfterRestart();

  // The running rig job's progress (null when none): for /status and the snapshot.
  nlohmann::json CurrentJob() const;
  // The last image each camera delivered during the running capture (empty when none).
  cv::Mat LastFrame(Side side) const;

 private:
  struct Running;
  // The rig for a job of `kind`, or 409 naming who holds it or which device is missing.
  std::variant<std::unique_ptr<RigLease>, JobError> LeaseRig(JobKind kind,
                                                             const std::string& station);
  void StartRigJob(const Job& job, std::unique_ptr<RigLease> lease);
  void RunRigJob(Running* run);
  void OnCaptureEvent(Running* run, const CaptureEvent& e);
  void ProcessLoop();
  void RunProcessJob(const Job& job);
  void RunCalibrateJob(const Job& job);
  void RunCalibrateFieldJob(const Job& job);
  // A calibrate job's end: its report with the file it wrote, or why there is none.
  void FinishCalibrateJob(const Job& job, const std::string& out, Result<nlohmann::json> report);
  void SetState(Running* run, JobState state, const nlohmann::json& summary = nullptr,
                const std::string& error = "");
  // In the history first, then as an event.
  void Record(int64_t id, JobState state, const nlohmann::json& summary = nullptr,
              const std::string& error = "");
  void PublishJob(int64_t id);
  std::string StationDir(const std::string& station) const;
  std::string DirOf(const Job& job) const;  // where a job's capture goes

  const DaemonConfig config_;
  JobStore* store_;
  DeviceSupervisor* devices_;
  EventHub* events_;

  mutable std::mutex mutex_;
  std::unique_ptr<Running> rig_job_;  // the rig job running, if any
  std::thread rig_thread_;
  std::deque<int64_t> process_queue_;
  int64_t processing_id_ = 0;  // the process job running, 0 when none
  std::atomic<bool> cancel_processing_{false};
  std::condition_variable process_wake_;
  std::atomic<bool> quit_{false};  // the daemon stops: what runs is interrupted, not cancelled
  std::thread process_thread_;
};

}  // namespace ts::daemon
