#pragma once
// The daemon's job history in SQLite (WAL mode, so that readers never wait for the writer
// and a kill -9 loses no committed row). One row per job: its kind, station, parameters,
// state and times, the summary and the error. Thread-safe (one connection, a mutex).
#include <sqlite3.h>

#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace ts::daemon {

// calibrate_rig: the stage kinematics adjusted on stations' own seams (calibrate_job.h);
// capture_field: a control field's grid of stage poses, the views `calibrate stereo` takes.
// retake: poses of a captured station taken again (acquisition/retake.h), then processed.
enum class JobKind {
  kSurvey,
  kCapture,
  kProcess,
  kCalibrateRig,
  kCaptureField,
  kRetake,
  kCalibrateField
};
enum class JobState { kQueued, kCapturing, kProcessing, kDone, kFailed, kInterrupted, kCancelled };

const char* JobKindName(JobKind kind);
std::optional<JobKind> JobKindFromName(const std::string& name);
const char* JobStateName(JobState state);
bool IsFinal(JobState state);  // done, failed, interrupted or cancelled
bool UsesRig(JobKind kind);    // survey, capture, capture_field and retake drive the rig

struct Job {
  int64_t id = 0;
  JobKind kind = JobKind::kSurvey;
  std::string station;
  nlohmann::json parameters = nlohmann::json::object();
  JobState state = JobState::kQueued;
  std::string created_utc, started_utc, finished_utc;
  nlohmann::json summary;  // null until the job has one
  std::string error;
  std::string idempotency_key;
  nlohmann::json ToJson() const;
};

class JobStore {
 public:
  static Result<std::unique_ptr<JobStore>> Open(const std::string& file);
  ~JobStore();

  // A new queued job; with a key that an earlier job was created with, that job instead
  // (`*existed` set), so that a request sent twice starts one job.
  Result<Job> Create(const Job& job, bool* existed = nullptr);
  Result<Job> Get(int64_t id);
  std::optional<Job> FindByKey(const std::string& idempotency_key);
  std::vector<Job> List(int limit = 200);  // newest first
  // The state, and the summary/error when given; started_utc at the first running state,
  // finished_utc at a final one.
  Status SetState(int64_t id, JobState state, const nlohmann::json& summary = nullptr,
                  const std::string& error = "");
  Status SetParameters(int64_t id, const nlohmann::json& parameters);

  // At start: what the last daemon left running. Capturing jobs become interrupted (resume
  // them from the pairs on disk); processing jobs go back to queued, to run again; queued
  // ones stay queued. Returns the jobs to run, oldest first.
  std::vector<Job> RecoverAfterRestart();

 private:
  explicit JobStore(sqlite3* db) : db_(db) {}
  Status Exec(const std::string& sql);
  std::vector<Job> Query(const std::string& where_and_order, int64_t bind = 0);
  std::string Error(const std::string& what) const;

  sqlite3* db_;
  std::mutex mutex_;
};

}  // namespace ts::daemon
