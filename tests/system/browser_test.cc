// The operator's page in a real browser: Debian's chromium, headless, driven by puppeteer-core
// (tests/browser/page_test.mjs) against topostationd driving the simulated station. A whole
// station, the retake its verdict names, a second epoch and the comparison of the two, then a
// daemon killed mid-capture and the page offering the interrupted job for resume.
// Screenshots are kept in BUILD/test-artifacts/browser/.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>

#include "tests/system/sim_daemon_fixture.h"

namespace ts {
namespace {

using testing::DaemonProcess;

class BrowserTest : public testing::SimDaemonTest {
 protected:
  // node page_test.mjs SCENARIO ...: its exit status, its output in *output.
  int RunPage(const DaemonProcess& d, const std::string& scenario, std::string* output) {
    const std::string artifacts = std::string(TS_BINARY_DIR) + "/test-artifacts/browser";
    const std::string log = dir_ / (scenario + ".log");
    const std::string command = "cd " TS_SOURCE_DIR "/tests/browser && node page_test.mjs " +
                                scenario + " --url http://127.0.0.1:" + std::to_string(kApiPort) +
                                "/ --token " + d.token() + " --stations " + d.stations_dir() +
                                " --diffs " + (dir_ / "state/diffs") + " --artifacts " + artifacts +
                                " > " + log + " 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream in(log);
    *output = std::string((std::istreambuf_iterator<char>(in)), {});
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
};

TEST_F(BrowserTest, AStationAndASecondEpochComparedAllFromThePage) {
  Serve();
  auto d = StartDaemon();
  ASSERT_TRUE(WaitReady(*d));
  std::string output;
  EXPECT_EQ(RunPage(*d, "survey", &output), 0) << output << d->log();
  // What the page started are ordinary jobs: two surveys with the fields typed into the form,
  // and the retake of S1's verdict.
  const nlohmann::json jobs = d->GetJson("/jobs");
  ASSERT_EQ(jobs.size(), 3u) << jobs.dump();
  int surveys = 0;
  for (const nlohmann::json& job : jobs) {
    EXPECT_EQ(job["state"], "done") << job.dump();
    if (job["kind"] == "retake") continue;
    ++surveys;
    EXPECT_EQ(job["parameters"]["line"], "L7");
    EXPECT_EQ(job["parameters"]["instrument_height_m"], 1.52);
  }
  EXPECT_EQ(surveys, 2);
}

TEST_F(BrowserTest, AfterARestartMidCaptureThePageOffersTheJobForResume) {
  Serve();
  auto d = StartDaemon();
  ASSERT_TRUE(WaitReady(*d));
  std::string output;
  ASSERT_EQ(RunPage(*d, "start", &output), 0) << output << d->log();
  d->Kill(SIGKILL);  // the page's capture is under way: the unit loses power
  ASSERT_TRUE(d->Start()) << d->log();
  ASSERT_TRUE(WaitReady(*d));
  EXPECT_EQ(RunPage(*d, "resume", &output), 0) << output << d->log();
  const nlohmann::json jobs = d->GetJson("/jobs");
  ASSERT_EQ(jobs.size(), 1u) << jobs.dump();
  EXPECT_EQ(jobs[0]["state"], "done") << jobs.dump();
}

}  // namespace
}  // namespace ts
