#include "station/daemon/daemon_config.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts::daemon {
namespace {

std::string Write(const testing::TempDir& dir, const std::string& text) {
  const std::string file = dir / "daemon.yaml";
  std::ofstream(file) << text;
  return file;
}

TEST(DaemonConfig, ReadsEveryFieldWithPathsRelativeToTheFileAndTheStateDirectory) {
  testing::TempDir dir;
  const Result<DaemonConfig> c =
      LoadDaemonConfig(Write(dir,
                             "schema_version: 1\n"
                             "rig_file: rig.yaml\n"
                             "state_dir: state\n"
                             "listen: {address: 0.0.0.0, port: 9000}\n"
                             "allowed_hosts: [tripod.local]\n"
                             "device_poll_s: 0.5\n"
                             "headless: {mode: schedule, every_hours: 2, "
                             "station_pattern: 'mon-{utc}'}\n"));
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->rig_file, dir / "rig.yaml");
  EXPECT_EQ(c->state_dir, dir / "state");
  EXPECT_EQ(c->stations_dir, dir / "state/stations");
  EXPECT_EQ(c->token_file, dir / "state/token");
  EXPECT_EQ(c->JobDatabase(), dir / "state/jobs.sqlite");
  EXPECT_EQ(c->listen_address, "0.0.0.0");
  EXPECT_EQ(c->listen_port, 9000);
  EXPECT_EQ(c->allowed_hosts, std::vector<std::string>{"tripod.local"});
  EXPECT_EQ(c->device_poll_s, 0.5);
  EXPECT_EQ(c->headless.mode, HeadlessMode::kSchedule);
  EXPECT_EQ(c->headless.every_hours, 2.0);
}

TEST(DaemonConfig, ListensOnLoopbackUnlessConfigured) {
  testing::TempDir dir;
  const Result<DaemonConfig> c =
      LoadDaemonConfig(Write(dir, "schema_version: 1\nrig_file: r.yaml\nstate_dir: /var/x\n"));
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->listen_address, "127.0.0.1");
  EXPECT_EQ(c->listen_port, 8080);
  EXPECT_EQ(c->headless.mode, HeadlessMode::kOff);
}

TEST(DaemonConfig, EachBadFieldIsNamedWithTheFile) {
  testing::TempDir dir;
  const std::string head = "schema_version: 1\nrig_file: r.yaml\nstate_dir: s\n";
  const std::pair<std::string, std::string> cases[] = {
      {head + "listen: {port: 70000}\n", "listen.port"},
      {head + "lisen: {port: 80}\n", "lisen: unknown key"},
      {head + "device_poll_s: .nan\n", "device_poll_s"},
      {head + "headless: {mode: sometimes}\n", "headless.mode"},
      {head + "headless: {mode: when_ready, station_pattern: fixed}\n", "headless.station_pattern"},
      {head + "allowed_hosts: tripod\n", "allowed_hosts"},
      {head + "usb: {stage: 'zz:01'}\n", "usb.stage"},
      {head + "usb: {gnss: '0403:6001'}\n", "usb.gnss: unknown key"},
      {"schema_version: 1\nstate_dir: s\n", "rig_file: missing"},
  };
  for (const auto& [text, field] : cases) {
    const Result<DaemonConfig> c = LoadDaemonConfig(Write(dir, text));
    ASSERT_FALSE(c.ok()) << text;
    EXPECT_NE(c.error().find(dir / "daemon.yaml"), std::string::npos) << c.error();
    EXPECT_NE(c.error().find(field), std::string::npos) << c.error();
  }
}

TEST(StationId, OnlyLettersDigitsUnderscoreAndDashUpTo64) {
  EXPECT_TRUE(IsStationId("G-0412_b"));
  EXPECT_TRUE(IsStationId(std::string(64, 'a')));
  for (const std::string bad : {"", "..", "../etc", "a/b", "a b", "a.b", "%2e%2e", "é"})
    EXPECT_FALSE(IsStationId(bad)) << bad;
  EXPECT_FALSE(IsStationId(std::string(65, 'a')));
}

TEST(StationId, TheNextHeadlessIdIsTheLowestFreeNumber) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "site-1");
  std::filesystem::create_directories(dir / "site-2");
  const Result<std::string> id = NextStationId("site-{n}", dir.path().string());
  ASSERT_TRUE(id.ok()) << id.error();
  EXPECT_EQ(*id, "site-3");
  const Result<std::string> utc = NextStationId("m-{utc}", dir.path().string());
  ASSERT_TRUE(utc.ok());
  EXPECT_EQ(utc->size(), std::string("m-20261125T193000Z").size());
  EXPECT_FALSE(NextStationId("../{n}", dir.path().string()).ok());
}

}  // namespace
}  // namespace ts::daemon
