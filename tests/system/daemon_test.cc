// topostationd against the simulated station on loopback: a whole survey through the API, the
// API's guards, a kill -9 in the middle of a capture and of processing, a cancel, devices lost
// and back, and the headless unit. The daemon runs as a process of its own.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "processing/io/calibration_yaml.h"
#include "processing/io/control_field_file.h"
#include "processing/io/station_manifest.h"
#include "processing/io/station_validator.h"
#include "sim/sim_server.h"
#include "station/daemon/headless.h"
#include "tests/common/daemon_process.h"
#include "tests/common/temp_dir.h"
#include "tests/system/sim_daemon_fixture.h"

namespace ts {
namespace {

using namespace std::chrono_literals;
using testing::DaemonProcess;
using testing::Finished;
using testing::kSurvey;

// The daemon driving the simulated station (sim_daemon_fixture.h).
class DaemonTest : public testing::SimDaemonTest {};

// Server-sent events read on a thread of their own until `stop` is set.
class EventReader {
 public:
  explicit EventReader(const DaemonProcess& d)
      : client_(std::make_unique<httplib::Client>(d.Client())) {
    thread_ = std::thread([this] {
      std::string buffer;
      client_->Get("/api/v1/events", [&](const char* data, size_t n) {
        buffer.append(data, n);
        for (size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
          Parse(buffer.substr(0, end));
          buffer.erase(0, end + 2);
        }
        return !stop_;
      });
    });
  }
  ~EventReader() {
    stop_ = true;
    client_->stop();  // without waiting for the next heartbeat
    thread_.join();
  }
  std::vector<std::pair<uint64_t, std::pair<std::string, nlohmann::json>>> events() {
    std::lock_guard lock(mutex_);
    return events_;
  }

 private:
  void Parse(const std::string& block) {
    uint64_t id = 0;
    std::string type, data;
    std::istringstream lines(block);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("id: ", 0) == 0) id = std::stoull(line.substr(4));
      if (line.rfind("event: ", 0) == 0) type = line.substr(7);
      if (line.rfind("data: ", 0) == 0) data = line.substr(6);
    }
    if (type.empty()) return;  // a heartbeat
    std::lock_guard lock(mutex_);
    events_.push_back({id, {type, nlohmann::json::parse(data)}});
  }
  std::atomic<bool> stop_{false};
  std::unique_ptr<httplib::Client> client_;
  std::mutex mutex_;
  std::vector<std::pair<uint64_t, std::pair<std::string, nlohmann::json>>> events_;
  std::thread thread_;
};

std::string ReadFile(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST_F(DaemonTest, AWholeSurveyThroughTheApiGivesProductsEqualToTheFilesOnDisk) {
  Serve();
  auto d = StartDaemon();
  ASSERT_TRUE(WaitReady(*d)) << d->GetJson("/status").dump();
  EventReader reader(*d);
  std::this_thread::sleep_for(300ms);
  const auto started = std::chrono::steady_clock::now();
  // A double click over a bad link: one survey.
  auto first = d->Post("/jobs", kSurvey, {{"Idempotency-Key", "click-1"}});
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 201) << first->body;
  auto again = d->Post("/jobs", kSurvey, {{"Idempotency-Key", "click-1"}});
  ASSERT_EQ(again->status, 200) << again->body;
  const int64_t id = nlohmann::json::parse(first->body)["id"];
  EXPECT_EQ(nlohmann::json::parse(again->body)["id"], id);
  // A second rig job while this one runs: 409 with who holds the rig.
  nlohmann::json other = kSurvey;
  other["station"] = "S2";
  auto busy = d->Post("/jobs", other);
  EXPECT_EQ(busy->status, 409);
  EXPECT_NE(busy->body.find("in use"), std::string::npos) << busy->body;

  const nlohmann::json job = d->WaitForJob(id, Finished);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_EQ(job["state"], "done") << job.dump() << d->log();
  EXPECT_EQ(job["summary"]["pairs"], 12);
  EXPECT_EQ(job["summary"]["verdict"], "usable") << job.dump();
  EXPECT_GT(job["summary"]["terrain_correction_sigma_mgal"].get<double>(), 0.0);
  std::this_thread::sleep_for(1s);  // the last events

  // Events: a snapshot first, progress per pair at most twice a second, the job's end.
  const auto events = reader.events();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().second.first, "snapshot");
  int progress = 0, last_pairs = 0;
  bool saw_done = false;
  for (size_t i = 0; i < events.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(events[i].first, events[i - 1].first);
    }
    const auto& [type, data] = events[i].second;
    if (type == "progress") {
      ++progress;
      EXPECT_GE(data.value("pairs_done", 0), last_pairs);
      last_pairs = data.value("pairs_done", last_pairs);
    }
    saw_done = saw_done || (type == "job" && data["state"] == "done");
  }
  EXPECT_GE(progress, 5);
  EXPECT_LE(progress, 2 * seconds + 3);
  EXPECT_TRUE(saw_done);

  // The station as the API shows it, and every product equal to its file.
  const nlohmann::json station = d->GetJson("/stations/S1");
  ASSERT_TRUE(station.is_object());
  EXPECT_EQ(station["fields"]["line"], "L7");
  // The crew's instrument height reaches the tilt axis; L's origin lies its height below.
  const nlohmann::json& stage = station["manifest"]["calibration"]["stage"];
  EXPECT_NEAR(
      stage["height_above_mark_m"].get<double>() + stage["tilt_axis_offset_m"][2].get<double>(),
      1.52, 1e-12);
  EXPECT_LT(stage["height_above_mark_m"].get<double>(), 1.45);
  EXPECT_TRUE(station["terrain_correction"].is_object());
  const std::set<std::string> names = station["products"];
  for (const char* expected : {"dem.tif", "dem_std.tif", "points.ply", "panorama.png",
                               "terrain_correction.json", "report.json"})
    EXPECT_TRUE(names.count(expected)) << expected;
  for (const std::string& name : names) {
    auto r = d->Client().Get(("/api/v1/stations/S1/products/" + name).c_str());
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << name;
    EXPECT_EQ(r->body, ReadFile(d->stations_dir() + "/S1/products/" + name)) << name;
  }
  EXPECT_EQ(d->GetJson("/stations").size(), 1u);
  const Result<StationManifest> m =
      ValidateStation(d->stations_dir() + "/S1", {.require_complete = true});
  EXPECT_TRUE(m.ok()) << m.error();
  // A retake of one pose: its old images kept aside, the pair taken again, the station
  // processed anew and still valid.
  const nlohmann::json pose = station["manifest"]["capture_plan"][2];
  const std::string before = station["manifest"]["pairs"][2]["captured_utc"];
  auto retake = d->Post("/jobs", {{"kind", "retake"}, {"station", "S1"}, {"poses", {pose}}});
  ASSERT_EQ(retake->status, 201) << retake->body;
  const nlohmann::json retaken = d->WaitForJob(nlohmann::json::parse(retake->body)["id"], Finished);
  ASSERT_EQ(retaken["state"], "done") << retaken.dump();
  EXPECT_EQ(retaken["summary"]["captured_now"], 1) << retaken.dump();
  int kept = 0;
  for (const auto& e :
       std::filesystem::recursive_directory_iterator(d->stations_dir() + "/S1/retaken"))
    kept += e.is_regular_file();
  EXPECT_EQ(kept, 2);
  const Result<StationManifest> after_retake =
      ValidateStation(d->stations_dir() + "/S1", {.require_complete = true});
  ASSERT_TRUE(after_retake.ok()) << after_retake.error();
  for (const PairRecord& p : after_retake->pairs) {
    if (p.index == 2) {
      EXPECT_GT(p.captured_utc, before);
    }
  }
  // The stage calibrated on the station's own seams, as a job (a child process).
  EXPECT_EQ(d->Post("/jobs", {{"kind", "calibrate_rig"}, {"stations", {"S1", "S9"}}})->status, 404);
  auto calibrate = d->Post("/jobs", {{"kind", "calibrate_rig"}, {"stations", {"S1"}}});
  ASSERT_EQ(calibrate->status, 201) << calibrate->body;
  const nlohmann::json calibrated =
      d->WaitForJob(nlohmann::json::parse(calibrate->body)["id"], Finished);
  ASSERT_EQ(calibrated["state"], "done") << calibrated.dump();
  const Result<Calibration> cal =
      LoadCalibrationYaml(calibrated["summary"]["calibration_file"].get<std::string>());
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_GT(calibrated["summary"]["tie_points"].get<int>(), 100) << calibrated.dump();
  // The rig's design cameras carry no precision: refining them fails with the reason.
  auto refine =
      d->Post("/jobs", {{"kind", "calibrate_rig"}, {"stations", {"S1"}}, {"refine_cameras", true}});
  ASSERT_EQ(refine->status, 201) << refine->body;
  const nlohmann::json refused = d->WaitForJob(nlohmann::json::parse(refine->body)["id"], Finished);
  EXPECT_EQ(refused["state"], "failed") << refused.dump();
  EXPECT_NE(refused.dump().find("cameras.left: no precision"), std::string::npos) << refused.dump();
  // A taped height below the stage's own tilt axis over its origin: failed before any capture,
  // the field named.
  auto low =
      d->Post("/jobs", {{"kind", "survey"}, {"station", "S2"}, {"instrument_height_m", 0.1}});
  ASSERT_EQ(low->status, 201) << low->body;
  const nlohmann::json too_low = d->WaitForJob(nlohmann::json::parse(low->body)["id"], Finished);
  EXPECT_EQ(too_low["state"], "failed") << too_low.dump();
  EXPECT_NE(too_low.dump().find("instrument_height_m: instrument height 0.1 m: below"),
            std::string::npos)
      << too_low.dump();
  // A preview now comes from the camera itself.
  auto jpeg = d->Client().Get("/api/v1/cameras/left/snapshot.jpg");
  ASSERT_TRUE(jpeg);
  EXPECT_EQ(jpeg->status, 200) << jpeg->body;
  EXPECT_EQ(jpeg->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_EQ(jpeg->body.substr(0, 2), "\xFF\xD8");
}

TEST_F(DaemonTest, EveryRouteThatMovesOrWritesNeedsTheTokenAndForeignHostsAreRefused) {
  auto d = StartDaemon();  // no rig served: the daemon starts without its devices
  httplib::Client c = d->Client();
  const std::vector<std::pair<std::string, std::string>> writes = {
      {"/api/v1/jobs", kSurvey.dump()},
      {"/api/v1/jobs/1/cancel", ""},
      {"/api/v1/jobs/1/resume", ""},
      {"/api/v1/stage/home", ""},
      {"/api/v1/stage/move", R"({"pan_deg": 10, "tilt_deg": 0})"},
      {"/api/v1/stage/stop", ""},
      {"/api/v1/diffs", R"({"before": "S1", "after": "S2"})"}};
  int failures = 0;
  for (const auto& [path, body] : writes)
    for (const httplib::Headers& headers :
         {httplib::Headers{}, httplib::Headers{{"Authorization", "Bearer " + std::string(64, '0')}},
          httplib::Headers{{"Authorization", d->token()}}}) {
      auto r = c.Post(path.c_str(), headers, body, "application/json");
      ASSERT_TRUE(r);
      EXPECT_EQ(r->status, 401) << path;
      // A right token clears the client's record before the throttle would answer instead.
      if (++failures % 4 == 0) {
        EXPECT_EQ(d->Post("/jobs/999/cancel", {})->status, 404);
      }
    }
  // Reads need no token; the health check never does.
  EXPECT_EQ(c.Get("/api/v1/status")->status, 200);
  EXPECT_EQ(c.Get("/api/v1/health")->status, 200);
  // DNS rebinding: a page of another name reaching this address.
  httplib::Headers evil_host = {{"Host", "evil.example:18321"}};
  EXPECT_EQ(c.Get("/api/v1/status", evil_host)->status, 403);
  EXPECT_EQ(c.Get("/api/v1/health", evil_host)->status, 403);
  // A page of another origin posting with a stolen token; no CORS header is ever sent.
  auto foreign = d->Post("/jobs", kSurvey, {{"Origin", "http://evil.example"}});
  EXPECT_EQ(foreign->status, 403);
  EXPECT_FALSE(foreign->has_header("Access-Control-Allow-Origin"));
  EXPECT_NE(d->Post("/jobs", kSurvey, {{"Origin", "http://127.0.0.1:18321"}})->status, 403);
  // 64 KiB bodies at most.
  nlohmann::json big = kSurvey;
  big["notes"] = std::string(70 * 1024, 'x');
  EXPECT_EQ(d->Post("/jobs", big)->status, 413);
  // No path from request text: every traversal is refused and nothing is created.
  nlohmann::json traversal = kSurvey;
  traversal["station"] = "../../escaped";
  auto refused = d->Post("/jobs", traversal);
  EXPECT_EQ(refused->status, 400);
  EXPECT_NE(refused->body.find("station"), std::string::npos);
  EXPECT_EQ(c.Get("/api/v1/stations/..%2F..%2Fstate")->status, 404);
  EXPECT_EQ(c.Get("/api/v1/stations/S1/products/..%2F..%2Ftoken")->status, 404);
  EXPECT_EQ(c.Get("/api/v1/stations/..%2Fstate/products/token")->status, 404);
  // The page's routes: each bad request one clear answer naming what is wrong.
  for (const char* path :
       {"/api/v1/stations/..%2F..%2Fstate/station.zip", "/api/v1/stations/S9/station.zip",
        "/api/v1/stations/S9/pairs/0/left.jpg", "/api/v1/diffs/S1--S2/dod.png",
        "/api/v1/diffs/..--..%2Ftoken/change.json"})
    EXPECT_EQ(c.Get(path)->status, 404) << path;
  auto no_stations = c.Get("/api/v1/campaign.csv");
  EXPECT_EQ(no_stations->status, 404);
  EXPECT_NE(no_stations->body.find("no station"), std::string::npos) << no_stations->body;
  auto no_before = d->Post("/diffs", {{"after", "S2"}});
  EXPECT_EQ(no_before->status, 400);
  EXPECT_NE(no_before->body.find("before"), std::string::npos) << no_before->body;
  auto unknown = d->Post("/diffs", {{"before", "S1"}, {"after", "../S2"}});
  EXPECT_EQ(unknown->status, 404);
  EXPECT_NE(unknown->body.find("before: no such station"), std::string::npos) << unknown->body;
  EXPECT_EQ(c.Get("/")->status, 200);
  EXPECT_EQ(c.Get("/")->get_header_value("Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(c.Get("/")->get_header_value("Content-Security-Policy").find("default-src 'self'"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "escaped"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "state/escaped"));
  EXPECT_TRUE(std::filesystem::is_empty(d->stations_dir()));
  // A rig job without the rig: 409 with the device that is missing.
  auto missing = d->Post("/jobs", kSurvey);
  EXPECT_EQ(missing->status, 409);
  EXPECT_NE(missing->body.find("absent"), std::string::npos) << missing->body;
  // A client that keeps guessing is slowed down, even when it then sends the right token.
  for (int i = 0; i < 5; ++i) c.Post("/api/v1/stage/stop", httplib::Headers{}, "", "text/plain");
  auto slowed = d->Post("/stage/stop", {});
  EXPECT_EQ(slowed->status, 429);
  EXPECT_EQ(slowed->get_header_value("Retry-After"), "1");
  std::this_thread::sleep_for(1100ms);
  EXPECT_NE(d->Post("/jobs/999/cancel", {})->status, 429);
}

// At most 8 event streams: each holds a server thread; the rest of the API still answers.
TEST_F(DaemonTest, ANinthEventStreamIsRefusedAndTheApiStillAnswers) {
  auto d = StartDaemon();
  std::vector<std::unique_ptr<EventReader>> readers;
  for (int i = 0; i < 8; ++i) readers.push_back(std::make_unique<EventReader>(*d));
  // Every stream connected (it had its snapshot) before the ninth asks: on a loaded machine a
  // reader's thread may connect late, and the ninth would then take its place.
  auto connected = [&] {
    return std::all_of(readers.begin(), readers.end(), [](const auto& r) {
      const auto events = r->events();
      return !events.empty() && events.front().second.first == "snapshot";
    });
  };
  for (int i = 0; i < 200 && !connected(); ++i) std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(connected());
  // The ninth reads no further than its first bytes: were it let in, the test fails, not hangs.
  int ninth_status = 0;
  d->Client().Get(
      "/api/v1/events", [&](const httplib::Response& r) { return ninth_status = r.status, true; },
      [](const char*, size_t) { return false; });
  EXPECT_EQ(ninth_status, 503);
  EXPECT_EQ(d->Client().Get("/api/v1/status")->status, 200);
  readers.clear();
}

std::map<int, std::string> PairShas(const std::string& station_dir) {
  std::map<int, std::string> shas;
  const Result<StationManifest> m = LoadStationManifest(station_dir);
  if (m)
    for (const PairRecord& p : m->pairs) shas[p.index] = p.left.sha256 + p.right.sha256;
  return shas;
}

// kill -9 in the middle of a capture: the job is interrupted, resuming it completes the station
// with no pair lost, changed or duplicated. Then kill -9 during processing: it finishes after
// the restart by itself.
TEST_F(DaemonTest, KilledMidCaptureTheJobResumesAndKilledMidProcessingItRunsAgain) {
  Serve();
  auto d = StartDaemon();
  ASSERT_TRUE(WaitReady(*d));
  const int64_t id = StartSurvey(*d);
  ASSERT_GT(id, 0);
  ASSERT_GE(WaitForPairs(*d, 4), 4);
  d->Kill(SIGKILL);
  const std::string station = d->stations_dir() + "/S1";
  const std::map<int, std::string> before = PairShas(station);
  ASSERT_GE(before.size(), 4u);
  ASSERT_LT(before.size(), 12u);

  ASSERT_TRUE(d->Start()) << d->log();
  const nlohmann::json interrupted = d->GetJson("/jobs/" + std::to_string(id));
  EXPECT_EQ(interrupted["state"], "interrupted") << interrupted.dump();
  EXPECT_NE(interrupted["error"].get<std::string>().find("resume"), std::string::npos);
  EXPECT_TRUE(ValidateStation(station, {}).ok());
  ASSERT_TRUE(WaitReady(*d));
  auto resumed = d->Post("/jobs/" + std::to_string(id) + "/resume", {});
  ASSERT_EQ(resumed->status, 200) << resumed->body;
  const nlohmann::json done = d->WaitForJob(id, Finished);
  ASSERT_EQ(done["state"], "done") << done.dump() << d->log();
  EXPECT_EQ(done["summary"]["captured_now"].get<int>() + static_cast<int>(before.size()), 12);
  const Result<StationManifest> m = ValidateStation(station, {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_EQ(m->pairs.size(), 12u);  // none duplicated
  const std::map<int, std::string> after = PairShas(station);
  for (const auto& [index, sha] : before) EXPECT_EQ(after.at(index), sha) << "pair " << index;

  // Reprocessing the station, killed while it runs.
  auto process = d->Post("/jobs", {{"kind", "process"}, {"station", "S1"}});
  ASSERT_EQ(process->status, 201) << process->body;
  const int64_t pid = nlohmann::json::parse(process->body)["id"];
  ASSERT_FALSE(d->WaitForJob(pid, [](const nlohmann::json& j) {
                  return j["state"] == "processing";
                }).is_null());
  d->Kill(SIGKILL);
  const auto killed_at = std::filesystem::file_time_type::clock::now();
  ASSERT_TRUE(d->Start()) << d->log();
  const nlohmann::json reprocessed = d->WaitForJob(pid, Finished);
  ASSERT_EQ(reprocessed["state"], "done") << reprocessed.dump() << d->log();
  EXPECT_GT(std::filesystem::last_write_time(station + "/products/report.json"), killed_at);
}

// Cancel stops the stage at once (not at the next pair) and leaves a station that validates.
TEST_F(DaemonTest, CancelStopsTheStageAtOnceAndLeavesAStationThatValidates) {
  Serve();
  auto d = StartDaemon();
  ASSERT_TRUE(WaitReady(*d));
  const int64_t id = StartSurvey(*d);
  ASSERT_GT(id, 0);
  WaitForPairs(*d, 2);
  // Cancel while the stage turns to the next pose.
  for (int i = 0; i < 200; ++i) {
    const StagePose a = server_->stage().Pose();
    std::this_thread::sleep_for(20ms);
    const StagePose b = server_->stage().Pose();
    if (std::abs(a.pan_deg - b.pan_deg) > 0.05) break;
  }
  auto cancel = d->Post("/jobs/" + std::to_string(id) + "/cancel", {});
  ASSERT_EQ(cancel->status, 200) << cancel->body;
  const auto cancelled_at = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(400ms);  // one status poll and the stage's deceleration
  const StagePose a = server_->stage().Pose();
  std::this_thread::sleep_for(300ms);
  const StagePose b = server_->stage().Pose();
  EXPECT_NEAR(a.pan_deg, b.pan_deg, 0.01) << "the stage still turns after the cancel";
  const nlohmann::json job = d->WaitForJob(id, Finished, 10s);
  ASSERT_EQ(job["state"], "cancelled") << job.dump();
  EXPECT_LT(std::chrono::steady_clock::now() - cancelled_at, 5s);
  const Result<StationManifest> m = ValidateStation(d->stations_dir() + "/S1", {});
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_LT(m->pairs.size(), 12u);
}

// A camera lost and back, the stage unplugged and back: the states follow, a job that needed
// the camera fails naming it, and the next job runs.
TEST_F(DaemonTest, DevicesLostAndBackChangeStateAndTheNextJobRuns) {
  Serve();
  auto d = StartDaemon();
  ASSERT_TRUE(WaitReady(*d));
  auto state_of = [&](const std::string& device) {
    return d->GetJson("/status")["devices"][device]["state"].get<std::string>();
  };
  auto wait_state = [&](const std::string& device, const std::string& want) {
    for (int i = 0; i < 100 && state_of(device) != want; ++i) std::this_thread::sleep_for(100ms);
    return state_of(device);
  };
  const int64_t id = StartSurvey(*d);
  ASSERT_GT(id, 0);
  WaitForPairs(*d, 2);
  server_->camera(Side::kRight).Stop();  // gone longer than the capture waits for it
  const nlohmann::json failed = d->WaitForJob(id, Finished, 60s);
  ASSERT_EQ(failed["state"], "failed") << failed.dump();
  EXPECT_NE(failed["error"].get<std::string>().find("TS-SIM-R"), std::string::npos)
      << failed.dump();
  EXPECT_EQ(wait_state("right_camera", "absent"), "absent");
  EXPECT_EQ(state_of("left_camera"), "present");
  auto refused =
      d->Post("/jobs", {{"kind", "survey"}, {"station", "S2"}, {"instrument_height_m", 1.5}});
  EXPECT_EQ(refused->status, 409);
  EXPECT_NE(refused->body.find("TS-SIM-R"), std::string::npos) << refused->body;
  ASSERT_TRUE(server_->camera(Side::kRight).Start().ok());
  EXPECT_EQ(wait_state("right_camera", "present"), "present");

  server_.reset();  // the whole station unplugged
  EXPECT_EQ(wait_state("stage", "absent"), "absent");
  Serve();
  EXPECT_EQ(wait_state("stage", "present"), "present");
  ASSERT_TRUE(WaitReady(*d));
  nlohmann::json next = kSurvey;
  next["station"] = "S3";
  const int64_t again = StartSurvey(*d, next);
  ASSERT_GT(again, 0);
  EXPECT_EQ(d->WaitForJob(again, Finished)["state"], "done") << d->log();
}

// USB presence from libusb hotplug: a stage whose USB-serial adapter is unplugged is absent
// with that reason, though something answers on its port; plugged in, the poll takes over.
TEST_F(DaemonTest, AnUnpluggedUsbDeviceIsAbsentWithThatReason) {
  Serve();
  {  // the daemon with libusb's watcher: this machine has no such adapter
    auto d = StartDaemon("usb: {stage: '0403:6001'}\n");
    std::this_thread::sleep_for(1s);
    const nlohmann::json stage = d->GetJson("/status")["devices"]["stage"];
    EXPECT_EQ(stage["state"], "absent") << stage.dump();
    EXPECT_NE(stage["reason"].get<std::string>().find("0403:6001 is unplugged"), std::string::npos)
        << stage.dump();
    EXPECT_EQ(d->Post("/jobs", kSurvey)->status, 409);
  }
  // The supervisor's side of a hotplug event, in-process.
  daemon::DeviceSupervisor devices(*LoadRigConfig(WriteRig()), 100ms, {});
  auto stage_becomes = [&](const std::string& want) {
    for (int i = 0; i < 100 && devices.DevicesJson()["stage"]["state"] != want; ++i)
      std::this_thread::sleep_for(100ms);
    return devices.DevicesJson()["stage"]["state"].get<std::string>();
  };
  EXPECT_EQ(stage_becomes("present"), "present");
  devices.SetUsbPresence("stage", "0403:6001", false);
  EXPECT_EQ(stage_becomes("absent"), "absent");
  EXPECT_NE(devices.DevicesJson()["stage"]["reason"].get<std::string>().find("unplugged"),
            std::string::npos);
  devices.SetUsbPresence("stage", "0403:6001", true);
  EXPECT_EQ(stage_becomes("present"), "present");
}

// The headless unit: a survey as soon as the rig is ready, an ordinary job in the history; a
// SIGTERM during its capture marks it interrupted.
TEST_F(DaemonTest, HeadlessWhenReadyStartsASurveyOfItsOwnAndSigtermInterruptsIt) {
  auto d = StartDaemon(
      "headless: {mode: when_ready, station_pattern: 'auto-{n}', line: H, "
      "instrument_height_m: 1.4}\n");
  std::this_thread::sleep_for(1500ms);
  EXPECT_TRUE(d->GetJson("/jobs").empty());  // no rig yet: nothing starts
  Serve();
  const nlohmann::json job = d->WaitForJob(
      1, [](const nlohmann::json& j) { return j["state"] == "capturing"; }, 30s);
  ASSERT_FALSE(job.is_null()) << d->log();
  EXPECT_EQ(job["station"], "auto-1");
  EXPECT_EQ(job["parameters"]["line"], "H");
  EXPECT_EQ(job["parameters"]["instrument_height_m"], 1.4);
  WaitForPairs(*d, 1);
  EXPECT_EQ(WEXITSTATUS(d->Kill(SIGTERM)), 0);
  // Read the history the daemon left, as the next start will.
  auto store = DaemonProcess(dir_.path().string(), kApiPort, WriteRig());
  ASSERT_TRUE(store.Start());
  const nlohmann::json after = store.GetJson("/jobs/1");
  EXPECT_EQ(after["state"], "interrupted") << after.dump();
  EXPECT_EQ(store.GetJson("/jobs").size(), 1u);  // once: no second survey of its own
  EXPECT_TRUE(ValidateStation(d->stations_dir() + "/auto-1", {}).ok());
}

// The control field's JSON as a client sends it: FIELD.yaml's and MARKS.yaml's content.
nlohmann::json FieldJson(const ControlField& field) {
  nlohmann::json targets = nlohmann::json::array();
  for (const FieldTarget& t : field.targets)
    targets.push_back({{"id", t.id},
                       {"x", t.position_m.x()},
                       {"y", t.position_m.y()},
                       {"z", t.position_m.z()},
                       {"sigma_m", t.sigma_m},
                       {"diameter_m", t.diameter_m}});
  return {{"version", 1}, {"targets", targets}};
}

nlohmann::json MarksJson(const std::vector<ImageMarks>& marks) {
  nlohmann::json all = nlohmann::json::array();
  for (const ImageMarks& image : marks) {
    nlohmann::json targets = nlohmann::json::array();
    for (const TargetMark& m : image.marks)
      targets.push_back({{"id", m.id}, {"x", m.pixel.x()}, {"y", m.pixel.y()}});
    all.push_back({{"image", image.image}, {"targets", targets}});
  }
  return all;
}

// A control field through the API, as a field team with only the page's laptop works: the
// grid of stage poses captured as a session that validates, with the design cameras it starts
// from beside it; then the field and the hand marks sent as a calibrate_field job, which
// calibrates the cameras, the stereo pair and the rig's height over the tilt axis near the
// truth.
TEST_F(DaemonTest, AControlFieldSessionIsCapturedAndCalibratedAsJobs) {
  sim::ServedCalibration targets;
  targets.kind = "field";
  targets.field.poses.pans = 5;  // fewer poses than the default grid: a quicker test
  targets.field.poses.tilts = 3;
  Serve(targets);
  const Calibration design = station_->rig.nominal;
  auto d = StartDaemon("", &design);
  ASSERT_TRUE(WaitReady(*d));
  auto r = d->Post("/jobs", {{"kind", "capture_field"},
                             {"station", "field-1"},
                             {"field_pans", targets.field.poses.pans},
                             {"field_tilts", targets.field.poses.tilts}});
  ASSERT_EQ(r->status, 201) << r->body;
  const nlohmann::json job = d->WaitForJob(nlohmann::json::parse(r->body)["id"], Finished, 120s);
  ASSERT_EQ(job["state"], "done") << job.dump() << d->log();
  ASSERT_TRUE(job["summary"]["session"].is_string()) << job.dump();
  const std::string session = job["summary"]["session"];
  EXPECT_EQ(session, dir_ / "state/calibration-sessions/field-1");
  const Result<StationManifest> m = ValidateStation(session, {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  const std::vector<StagePose> plan = MakeFieldPoseGrid(targets.field.poses);
  ASSERT_EQ(m->plan.size(), plan.size());
  for (size_t k = 0; k < plan.size(); ++k) EXPECT_EQ(m->plan[k].tilt_deg, plan[k].tilt_deg);
  EXPECT_TRUE(LoadCalibrationYaml(session + "/design.yaml").ok());
  EXPECT_NE(job["summary"]["next"].get<std::string>().find("calibrate_field"), std::string::npos);
  EXPECT_TRUE(d->GetJson("/stations").empty());  // a session is not a station

  const std::string truth = dir_ / "truth";
  std::filesystem::create_directories(truth);
  ASSERT_TRUE(
      sim::WriteServedCalibrationTruth(station_->rig, station_->scene.seed, targets, truth).ok());
  const nlohmann::json calibrate = {
      {"kind", "calibrate_field"},
      {"session", "field-1"},
      {"control_field", FieldJson(*LoadControlField(truth + "/field.yaml"))},
      {"marks", MarksJson(*LoadTargetMarks(truth + "/marks.yaml"))}};
  nlohmann::json elsewhere = calibrate;
  elsewhere["session"] = "field-2";
  EXPECT_EQ(d->Post("/jobs", elsewhere)->status, 404);
  nlohmann::json unknown_target = calibrate;
  unknown_target["marks"][0]["targets"][0]["id"] = 99999;
  r = d->Post("/jobs", unknown_target);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("marks[0].targets[0].id: 99999"), std::string::npos) << r->body;

  r = d->Post("/jobs", calibrate);
  ASSERT_EQ(r->status, 201) << r->body;
  const nlohmann::json done = d->WaitForJob(nlohmann::json::parse(r->body)["id"], Finished, 120s);
  ASSERT_EQ(done["state"], "done") << done.dump() << d->log();
  EXPECT_GT(done["summary"]["control_field"].value("targets_found", 0), 60) << done.dump();
  const Result<Calibration> cal = LoadCalibrationYaml(done["summary"]["calibration_file"]);
  ASSERT_TRUE(cal.ok()) << cal.error();
  const StereoRig& t = station_->rig.truth.rig;
  const double design_off =
      std::abs(design.rig.left.principal_distance_px - t.left.principal_distance_px);
  EXPECT_GT(design_off, 0.0005 * t.left.principal_distance_px);  // the design is off by more
  EXPECT_LT(std::abs(cal->rig.left.principal_distance_px - t.left.principal_distance_px),
            0.0005 * t.left.principal_distance_px);
  EXPECT_LT(std::abs(cal->rig.right.principal_distance_px - t.right.principal_distance_px),
            0.0005 * t.right.principal_distance_px);
  EXPECT_LT(std::abs(cal->rig.baseline_m - t.baseline_m), 0.0002);
  // The stage from the same session: the cameras placed over the tilt axis (the rig's offset
  // across it and above it: the design's is 1.6 and 0.6 mm off at this seed).
  EXPECT_TRUE(done["summary"]["stage"]["parameters"].is_object()) << done.dump();
  const Eigen::Vector3d& true_offset = station_->rig.truth.stage.rig_offset_m;
  EXPECT_GT(std::abs(design.stage.rig_offset_m.y() - true_offset.y()), 0.001);
  EXPECT_NEAR(cal->stage.rig_offset_m.y(), true_offset.y(), 0.0005);
  EXPECT_NEAR(cal->stage.rig_offset_m.z(), true_offset.z(), 0.0005);
  EXPECT_TRUE(std::filesystem::exists(session + "/marks-job-" + done["id"].dump() + ".yaml"));
}

// systemd's side (Type=notify): READY once listening, STATUS saying what it does, the
// watchdog fed while the device poll goes round, STOPPING on SIGTERM; read from a
// NOTIFY_SOCKET of the test's own, as systemd would.
TEST_F(DaemonTest, SystemdIsToldReadyWhatItDoesAndItsWatchdogIsFed) {
  const std::string path = dir_ / "notify.sock";
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  const timeval wait{0, 200000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof(wait));
  ::setenv("NOTIFY_SOCKET", path.c_str(), 1);
  auto d = StartDaemon();  // nothing served: idle, and the rig not ready
  ::unsetenv("NOTIFY_SOCKET");
  std::string said;
  auto listen = [&](std::chrono::milliseconds how_long) {
    const auto until = std::chrono::steady_clock::now() + how_long;
    char buffer[4096];
    while (std::chrono::steady_clock::now() < until) {
      const ssize_t n = ::recv(fd, buffer, sizeof(buffer), 0);
      if (n > 0) said += std::string(buffer, static_cast<size_t>(n)) + "\n";
    }
  };
  listen(2000ms);
  EXPECT_NE(said.find("READY=1"), std::string::npos) << said;
  EXPECT_NE(said.find("STATUS=idle, camera TS-SIM-L is absent"), std::string::npos) << said;
  EXPECT_NE(said.find("WATCHDOG=1"), std::string::npos) << said;
  said.clear();
  d->Kill(SIGTERM);
  listen(300ms);
  EXPECT_NE(said.find("STOPPING=1"), std::string::npos) << said;
  ::close(fd);
}

// A subsidence site watched on a schedule: a survey when the rig is ready, the next one only
// when its hours have passed; each an ordinary job (the parts in-process, the clock given).
TEST_F(DaemonTest, HeadlessScheduleSurveysAgainOnlyWhenItsHoursHavePassed) {
  Serve();
  daemon::DaemonConfig config;
  config.rig_file = WriteRig();
  config.state_dir = dir_ / "state";
  config.stations_dir = dir_ / "state/stations";
  config.headless = {daemon::HeadlessMode::kSchedule, "mon-{n}", "M", 1.5, 2.0};
  auto store = daemon::JobStore::Open(dir_ / "jobs.sqlite");
  ASSERT_TRUE(store.ok());
  daemon::EventHub events;
  daemon::DeviceSupervisor devices(*LoadRigConfig(config.rig_file), 200ms, {});
  daemon::JobRunner jobs(config, store->get(), &devices, &events);
  daemon::HeadlessScheduler headless(config, &devices, &jobs);
  for (int i = 0; i < 100 && !devices.WhyNotReady().empty(); ++i)
    std::this_thread::sleep_for(100ms);
  ASSERT_EQ(devices.WhyNotReady(), "");
  auto run_and_cancel = [&](int64_t id) {
    for (int i = 0; i < 100 && (*store)->Get(id)->state != daemon::JobState::kCapturing; ++i)
      std::this_thread::sleep_for(100ms);
    ASSERT_TRUE(std::holds_alternative<daemon::Job>(jobs.Cancel(id)));
    // An ended job is no longer current a moment before its thread gives the rig back; a tick
    // in between finds the rig in use and leaves the survey to the next tick, which this test
    // does not give.
    for (int i = 0; i < 100 && (!jobs.CurrentJob().is_null() ||
                                devices.DevicesJson()["stage"]["state"] == "in_use");
         ++i)
      std::this_thread::sleep_for(100ms);
    EXPECT_EQ((*store)->Get(id)->state, daemon::JobState::kCancelled);
  };
  const auto t0 = daemon::HeadlessScheduler::Clock::now();
  headless.Tick(t0);
  ASSERT_EQ((*store)->List().size(), 1u);
  EXPECT_EQ((*store)->Get(1)->station, "mon-1");
  run_and_cancel(1);
  headless.Tick(t0 + 1h);
  EXPECT_EQ((*store)->List().size(), 1u);  // not due yet
  headless.Tick(t0 + 2h + 1s);
  ASSERT_EQ((*store)->List().size(), 2u);
  EXPECT_EQ((*store)->Get(2)->station, "mon-2");
  EXPECT_EQ((*store)->Get(2)->parameters["line"], "M");
  run_and_cancel(2);
}

// `topostation survey --rig`: the same survey on a real rig without the daemon.
TEST_F(DaemonTest, TheSameSurveyRunsFromTheCommandLineWithoutTheDaemon) {
  Serve();
  const std::string station = dir_ / "cli-station";
  const testing::CommandOutput out =
      testing::RunCommand(std::string(TS_TOPOSTATION_EXE) + " survey --rig " + WriteRig() +
                          " --out " + station + " --instrument-height-m 1.45 --single-row --json");
  ASSERT_EQ(out.exit_code, 0) << out.out;
  const nlohmann::json j = nlohmann::json::parse(out.out);
  EXPECT_EQ(j["report"]["verdict"], "usable") << out.out;
  const Result<StationManifest> m = ValidateStation(station, {.require_complete = true});
  ASSERT_TRUE(m.ok()) << m.error();
  EXPECT_NEAR(m->calibration.stage.InstrumentHeightM(), 1.45, 1e-12);
  EXPECT_TRUE(std::filesystem::exists(station + "/products/terrain_correction.json"));
  // Neither or both of --sim and --rig: one clear line.
  const testing::CommandOutput neither = testing::RunCommand(
      std::string(TS_TOPOSTATION_EXE) + " survey --out " + (dir_ / "x") + " 2>&1");
  EXPECT_EQ(neither.exit_code, 1);
  EXPECT_NE(neither.out.find("--rig"), std::string::npos) << neither.out;
}

}  // namespace
}  // namespace ts
