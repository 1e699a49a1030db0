#pragma once
// topostationd as a process of its own (it must die by kill -9 and start again), with a
// config in a test's directory, and an HTTP client for its API. TS_TOPOSTATIOND_EXE is the
// daemon the build made.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include <httplib.h>  // NOLINT(build/include_order): after Eigen, see station/daemon/http_api.h

namespace ts::testing {

class DaemonProcess {
 public:
  // `extra_yaml`: more lines of the config (headless: ...).
  DaemonProcess(const std::string& dir, int port, const std::string& rig_file,
                const std::string& extra_yaml = "")
      : dir_(dir), port_(port) {
    config_ = dir + "/daemon.yaml";
    std::ofstream(config_) << "schema_version: 1\nrig_file: " << rig_file << "\nstate_dir: " << dir
                           << "/state\nlisten: {address: 127.0.0.1, "
                           << "port: " << port << "}\ndevice_poll_s: 0.3\n"
                           << extra_yaml;
  }
  ~DaemonProcess() { Kill(SIGKILL); }

  // Starts it and waits until /health answers (false after 20 s).
  bool Start() {
    const std::string log = dir_ + "/daemon.log";
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    const char* argv[] = {TS_TOPOSTATIOND_EXE, "--config", config_.c_str(), "-v", nullptr};
    const int spawned =
        posix_spawn(&pid_, argv[0], &actions, nullptr, const_cast<char* const*>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return false;
    for (int i = 0; i < 200; ++i) {
      if (auto r = Client().Get("/api/v1/health"); r && r->status == 200) return LoadToken();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }
  // Sends `signal` and waits for the process; its exit status (-1 when none ran).
  int Kill(int signal) {
    if (pid_ <= 0) return -1;
    ::kill(pid_, signal);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return status;
  }

  httplib::Client Client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(60, 0);
    return c;
  }
  httplib::Headers Auth() const { return {{"Authorization", "Bearer " + token_}}; }
  const std::string& token() const { return token_; }
  pid_t pid() const { return pid_; }
  std::string stations_dir() const { return dir_ + "/state/stations"; }
  std::string log() const {
    std::ifstream in(dir_ + "/daemon.log");
    return std::string((std::istreambuf_iterator<char>(in)), {});
  }

  nlohmann::json GetJson(const std::string& path) const {
    auto r = Client().Get(("/api/v1" + path).c_str());
    if (!r) return nullptr;
    return nlohmann::json::parse(r->body, nullptr, false);
  }
  // The response (status and body), with the token.
  httplib::Result Post(const std::string& path, const nlohmann::json& body,
                       httplib::Headers headers = {}) const {
    headers.emplace("Authorization", "Bearer " + token_);
    return Client().Post(("/api/v1" + path).c_str(), headers, body.dump(), "application/json");
  }
  // Polls GET /jobs/{id} until `done` holds of it (null after `timeout`).
  template <class Predicate>
  nlohmann::json WaitForJob(int64_t id, Predicate done,
                            std::chrono::seconds timeout = std::chrono::seconds(180)) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      const nlohmann::json job = GetJson("/jobs/" + std::to_string(id));
      if (job.is_object() && job.contains("state") && done(job)) return job;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return nullptr;
  }

 private:
  bool LoadToken() {
    std::ifstream in(dir_ + "/state/token");
    std::getline(in, token_);
    return token_.size() == 64;
  }
  std::string dir_, config_, token_;
  int port_;
  pid_t pid_ = -1;
};

inline bool Finished(const nlohmann::json& job) {
  const std::string s = job["state"];
  return s == "done" || s == "failed" || s == "cancelled" || s == "interrupted";
}

}  // namespace ts::testing
