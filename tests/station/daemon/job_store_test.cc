#include "station/daemon/job_store.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts::daemon {
namespace {

Job NewJob(JobKind kind, const std::string& station, const std::string& key = "") {
  Job j;
  j.kind = kind;
  j.station = station;
  j.parameters = {{"instrument_height_m", 1.5}};
  j.idempotency_key = key;
  return j;
}

TEST(JobStore, KeepsEveryJobWithItsStateTimesSummaryAndErrorAcrossReopening) {
  testing::TempDir dir;
  const std::string file = dir / "jobs.sqlite";
  int64_t id = 0;
  {
    auto store = JobStore::Open(file);
    ASSERT_TRUE(store.ok()) << store.error();
    const Result<Job> job = (*store)->Create(NewJob(JobKind::kSurvey, "S1"));
    ASSERT_TRUE(job.ok()) << job.error();
    id = job->id;
    EXPECT_EQ(job->state, JobState::kQueued);
    EXPECT_FALSE(job->created_utc.empty());
    EXPECT_TRUE(job->started_utc.empty());
    ASSERT_TRUE((*store)->SetState(id, JobState::kCapturing).ok());
    ASSERT_TRUE((*store)->SetState(id, JobState::kDone, {{"terrain_correction_mgal", 0.04}}).ok());
    ASSERT_TRUE((*store)->Create(NewJob(JobKind::kProcess, "S0")).ok());
    ASSERT_TRUE((*store)->SetState(id + 1, JobState::kFailed, nullptr, "pair 3: no match").ok());
  }
  auto store = JobStore::Open(file);
  ASSERT_TRUE(store.ok());
  const Result<Job> done = (*store)->Get(id);
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done->state, JobState::kDone);
  EXPECT_EQ(done->kind, JobKind::kSurvey);
  EXPECT_EQ(done->parameters["instrument_height_m"], 1.5);
  EXPECT_FALSE(done->started_utc.empty());
  EXPECT_FALSE(done->finished_utc.empty());
  EXPECT_EQ(done->summary["terrain_correction_mgal"], 0.04);
  const std::vector<Job> all = (*store)->List();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].error, "pair 3: no match");  // newest first
  EXPECT_FALSE((*store)->Get(999).ok());
}

TEST(JobStore, ARequestSentTwiceWithItsKeyIsOneJob) {
  testing::TempDir dir;
  auto store = JobStore::Open(dir / "jobs.sqlite");
  ASSERT_TRUE(store.ok());
  bool existed = true;
  const Result<Job> first = (*store)->Create(NewJob(JobKind::kSurvey, "S1", "k-1"), &existed);
  EXPECT_FALSE(existed);
  const Result<Job> again = (*store)->Create(NewJob(JobKind::kSurvey, "S1", "k-1"), &existed);
  EXPECT_TRUE(existed);
  EXPECT_EQ(again->id, first->id);
  const Result<Job> other = (*store)->Create(NewJob(JobKind::kSurvey, "S2", "k-2"), &existed);
  EXPECT_FALSE(existed);
  EXPECT_NE(other->id, first->id);
  EXPECT_EQ((*store)->List().size(), 2u);
}

TEST(JobStore, AfterADeathCapturesAreInterruptedAndProcessingRunsAgain) {
  testing::TempDir dir;
  auto store = JobStore::Open(dir / "jobs.sqlite");
  ASSERT_TRUE(store.ok());
  const int64_t capturing = (*store)->Create(NewJob(JobKind::kSurvey, "A"))->id;
  const int64_t processing = (*store)->Create(NewJob(JobKind::kSurvey, "B"))->id;
  const int64_t queued = (*store)->Create(NewJob(JobKind::kProcess, "C"))->id;
  const int64_t done = (*store)->Create(NewJob(JobKind::kCapture, "D"))->id;
  ASSERT_TRUE((*store)->SetState(capturing, JobState::kCapturing).ok());
  ASSERT_TRUE((*store)->SetState(processing, JobState::kProcessing).ok());
  ASSERT_TRUE((*store)->SetState(done, JobState::kDone).ok());

  const std::vector<Job> to_run = (*store)->RecoverAfterRestart();
  ASSERT_EQ(to_run.size(), 2u);
  EXPECT_EQ(to_run[0].id, processing);
  EXPECT_EQ(to_run[1].id, queued);
  EXPECT_EQ((*store)->Get(capturing)->state, JobState::kInterrupted);
  EXPECT_NE((*store)->Get(capturing)->error.find("resume"), std::string::npos);
  EXPECT_EQ((*store)->Get(processing)->state, JobState::kQueued);
  EXPECT_EQ((*store)->Get(done)->state, JobState::kDone);
}

TEST(JobStore, EveryKindKeepsItsNameThroughTheHistory) {
  testing::TempDir dir;
  auto store = JobStore::Open(dir / "jobs.sqlite");
  ASSERT_TRUE(store.ok());
  for (JobKind kind : {JobKind::kSurvey, JobKind::kCapture, JobKind::kProcess,
                       JobKind::kCalibrateRig, JobKind::kCaptureField}) {
    EXPECT_EQ(JobKindFromName(JobKindName(kind)), kind);
    const Result<Job> job = (*store)->Create(NewJob(kind, "S"));
    ASSERT_TRUE(job.ok());
    EXPECT_EQ((*store)->Get(job->id)->kind, kind) << JobKindName(kind);
  }
  EXPECT_FALSE(JobKindFromName("dance").has_value());
}

TEST(JobStore, TheHistoryIsInWalMode) {
  testing::TempDir dir;
  auto store = JobStore::Open(dir / "jobs.sqlite");
  ASSERT_TRUE(store.ok());
  ASSERT_TRUE((*store)->Create(NewJob(JobKind::kSurvey, "S")).ok());
  EXPECT_TRUE(std::filesystem::exists(dir / "jobs.sqlite-wal"));
}

TEST(JobStore, AFileThatIsNotADatabaseIsOneError) {
  testing::TempDir dir;
  std::ofstream(dir / "jobs.sqlite") << "not sqlite at all, but long enough to be read as a header";
  auto store = JobStore::Open(dir / "jobs.sqlite");
  ASSERT_FALSE(store.ok());
  EXPECT_NE(store.error().find("jobs.sqlite"), std::string::npos) << store.error();
}

}  // namespace
}  // namespace ts::daemon
