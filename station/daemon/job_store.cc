#include "station/daemon/job_store.h"

#include <array>

#include "core/log.h"
#include "processing/io/station_manifest.h"

namespace ts::daemon {
namespace {

constexpr std::array<const char*, 7> kKindNames = {
    "survey", "capture", "process", "calibrate_rig", "capture_field", "retake", "calibrate_field"};
static_assert(kKindNames.size() == static_cast<size_t>(JobKind::kCalibrateField) + 1,
              "a name for every JobKind");
constexpr std::array<const char*, 7> kStateNames = {"queued", "capturing",   "processing", "done",
                                                    "failed", "interrupted", "cancelled"};

// A statement, finalised on every path.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) stmt_ = nullptr;
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  bool ok() const { return stmt_ != nullptr; }
  void Bind(int i, const std::string& text) {
    sqlite3_bind_text(stmt_, i, text.c_str(), -1, SQLITE_TRANSIENT);
  }
  void Bind(int i, int64_t v) { sqlite3_bind_int64(stmt_, i, v); }
  void BindOrNull(int i, const std::string& text) {
    if (text.empty())
      sqlite3_bind_null(stmt_, i);
    else
      Bind(i, text);
  }
  int Step() { return sqlite3_step(stmt_); }
  std::string Text(int column) const {
    const unsigned char* t = sqlite3_column_text(stmt_, column);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  int64_t Int(int column) const { return sqlite3_column_int64(stmt_, column); }

 private:
  sqlite3_stmt* stmt_ = nullptr;
};

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS jobs (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  kind TEXT NOT NULL,
  station TEXT NOT NULL,
  parameters TEXT NOT NULL,
  state TEXT NOT NULL,
  created_utc TEXT NOT NULL,
  started_utc TEXT,
  finished_utc TEXT,
  summary TEXT,
  error TEXT,
  idempotency_key TEXT UNIQUE
);)sql";

constexpr const char* kColumns =
    "SELECT id, kind, station, parameters, state, created_utc, started_utc, finished_utc, "
    "summary, error, idempotency_key FROM jobs ";

JobState StateFromName(const std::string& name) {
  for (size_t i = 0; i < kStateNames.size(); ++i)
    if (name == kStateNames[i]) return static_cast<JobState>(i);
  return JobState::kFailed;
}

nlohmann::json JsonOrNull(const std::string& text) {
  if (text.empty()) return nullptr;
  return nlohmann::json::parse(text, nullptr, false);
}

}  // namespace

const char* JobKindName(JobKind kind) { return kKindNames[static_cast<size_t>(kind)]; }
const char* JobStateName(JobState state) { return kStateNames[static_cast<size_t>(state)]; }

std::optional<JobKind> JobKindFromName(const std::string& name) {
  for (size_t i = 0; i < kKindNames.size(); ++i)
    if (name == kKindNames[i]) return static_cast<JobKind>(i);
  return std::nullopt;
}

bool IsFinal(JobState s) {
  return s == JobState::kDone || s == JobState::kFailed || s == JobState::kInterrupted ||
         s == JobState::kCancelled;
}

bool UsesRig(JobKind kind) {
  return kind == JobKind::kSurvey || kind == JobKind::kCapture || kind == JobKind::kCaptureField ||
         kind == JobKind::kRetake;
}

nlohmann::json Job::ToJson() const {
  auto or_null = [](const std::string& s) -> nlohmann::json {
    if (s.empty()) return nullptr;
    return s;
  };
  return {{"id", id},
          {"kind", JobKindName(kind)},
          {"station", station},
          {"parameters", parameters},
          {"state", JobStateName(state)},
          {"created_utc", created_utc},
          {"started_utc", or_null(started_utc)},
          {"finished_utc", or_null(finished_utc)},
          {"summary", summary},
          {"error", or_null(error)}};
}

Result<std::unique_ptr<JobStore>> JobStore::Open(const std::string& file) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(file.c_str(), &db,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    return ts::Error{file + ": cannot open the job history: " + why};
  }
  std::unique_ptr<JobStore> store(new JobStore(db));
  sqlite3_busy_timeout(db, 5000);
  for (const char* sql : {"PRAGMA journal_mode=WAL;", "PRAGMA synchronous=NORMAL;", kSchema})
    if (Status s = store->Exec(sql); !s) return ts::Error{file + ": " + s.error()};
  return store;
}

JobStore::~JobStore() { sqlite3_close(db_); }

std::string JobStore::Error(const std::string& what) const {
  return what + ": " + sqlite3_errmsg(db_);
}

Status JobStore::Exec(const std::string& sql) {
  char* message = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string why = message ? message : "error";
    sqlite3_free(message);
    return ts::Error{"job history: " + why};
  }
  return {};
}

std::vector<Job> JobStore::Query(const std::string& where_and_order, int64_t bind) {
  Statement q(db_, kColumns + where_and_order);
  std::vector<Job> jobs;
  if (!q.ok()) return jobs;
  if (where_and_order.find('?') != std::string::npos) q.Bind(1, bind);
  while (q.Step() == SQLITE_ROW) {
    Job j;
    j.id = q.Int(0);
    j.kind = JobKindFromName(q.Text(1)).value_or(JobKind::kProcess);
    j.station = q.Text(2);
    j.parameters = JsonOrNull(q.Text(3));
    j.state = StateFromName(q.Text(4));
    j.created_utc = q.Text(5);
    j.started_utc = q.Text(6);
    j.finished_utc = q.Text(7);
    j.summary = JsonOrNull(q.Text(8));
    j.error = q.Text(9);
    j.idempotency_key = q.Text(10);
    jobs.push_back(std::move(j));
  }
  return jobs;
}

Result<Job> JobStore::Create(const Job& job, bool* existed) {
  if (existed) *existed = false;
  if (!job.idempotency_key.empty())
    if (std::optional<Job> earlier = FindByKey(job.idempotency_key)) {
      if (existed) *existed = true;
      return *earlier;
    }
  std::lock_guard lock(mutex_);
  Statement insert(db_,
                   "INSERT INTO jobs (kind, station, parameters, state, created_utc, "
                   "idempotency_key) VALUES (?, ?, ?, 'queued', ?, ?)");
  insert.Bind(1, std::string(JobKindName(job.kind)));
  insert.Bind(2, job.station);
  insert.Bind(3, job.parameters.dump());
  insert.Bind(4, UtcNowIso8601());
  insert.BindOrNull(5, job.idempotency_key);
  if (insert.Step() != SQLITE_DONE) return ts::Error{Error("job history: cannot add a job")};
  return Query("WHERE id = ?", sqlite3_last_insert_rowid(db_)).front();
}

Result<Job> JobStore::Get(int64_t id) {
  std::lock_guard lock(mutex_);
  std::vector<Job> jobs = Query("WHERE id = ?", id);
  if (jobs.empty()) return ts::Error{"no job " + std::to_string(id)};
  return jobs.front();
}

std::optional<Job> JobStore::FindByKey(const std::string& idempotency_key) {
  std::lock_guard lock(mutex_);
  Statement find(db_, "SELECT id FROM jobs WHERE idempotency_key = ?");
  find.Bind(1, idempotency_key);
  if (find.Step() != SQLITE_ROW) return std::nullopt;
  std::vector<Job> jobs = Query("WHERE id = ?", find.Int(0));
  if (jobs.empty()) return std::nullopt;
  return jobs.front();
}

std::vector<Job> JobStore::List(int limit) {
  std::lock_guard lock(mutex_);
  return Query("ORDER BY id DESC LIMIT ?", limit);
}

Status JobStore::SetState(int64_t id, JobState state, const nlohmann::json& summary,
                          const std::string& error) {
  std::lock_guard lock(mutex_);
  const bool running = state == JobState::kCapturing || state == JobState::kProcessing;
  Statement update(
      db_,
      "UPDATE jobs SET state = ?1, "
      "started_utc = CASE WHEN ?2 AND started_utc IS NULL THEN ?3 ELSE started_utc END, "
      "finished_utc = CASE WHEN ?4 THEN ?3 WHEN ?1 = 'queued' THEN NULL ELSE finished_utc END, "
      "summary = COALESCE(?5, summary), error = CASE WHEN ?1 = 'queued' THEN NULL "
      "ELSE COALESCE(?6, error) END WHERE id = ?7");
  update.Bind(1, std::string(JobStateName(state)));
  update.Bind(2, int64_t{running});
  update.Bind(3, UtcNowIso8601());
  update.Bind(4, int64_t{IsFinal(state)});
  update.BindOrNull(5, summary.is_null() ? std::string() : summary.dump());
  update.BindOrNull(6, error);
  update.Bind(7, id);
  if (update.Step() != SQLITE_DONE) return ts::Error{Error("job history: cannot update a job")};
  return {};
}

Status JobStore::SetParameters(int64_t id, const nlohmann::json& parameters) {
  std::lock_guard lock(mutex_);
  Statement update(db_, "UPDATE jobs SET parameters = ? WHERE id = ?");
  update.Bind(1, parameters.dump());
  update.Bind(2, id);
  if (update.Step() != SQLITE_DONE) return ts::Error{Error("job history: cannot update a job")};
  return {};
}

std::vector<Job> JobStore::RecoverAfterRestart() {
  std::vector<Job> unfinished;
  {
    std::lock_guard lock(mutex_);
    unfinished = Query("WHERE state IN ('queued', 'capturing', 'processing') ORDER BY id");
  }
  std::vector<Job> to_run;
  for (Job& job : unfinished) {
    if (job.state == JobState::kCapturing) {
      if (Status s = SetState(job.id, JobState::kInterrupted, nullptr,
                              "the daemon stopped during the capture; resume the job to capture "
                              "the pairs that are missing");
          !s)
        Log().error("{}", s.error());
      continue;
    }
    if (job.state == JobState::kProcessing)
      if (Status s = SetState(job.id, JobState::kQueued); !s) Log().error("{}", s.error());
    job.state = JobState::kQueued;
    to_run.push_back(job);
  }
  return to_run;
}

}  // namespace ts::daemon
