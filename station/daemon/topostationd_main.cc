// topostationd --config FILE.yaml [--print-token] [-v]: the daemon that owns the rig
// (station/daemon/daemon.h). SIGTERM and SIGINT stop it: a capture in progress is marked
// interrupted and resumes from its pairs; processing runs again at the next start.
#include <csignal>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "core/log.h"
#include "station/daemon/access_token.h"
#include "station/daemon/daemon.h"

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("topostationd: the daemon that owns the rig and serves its HTTP API");
  std::string config_file;
  bool print_token = false;
  int verbose = 0;
  app.add_option("--config", config_file, "daemon config (YAML)")->required();
  app.add_flag("--print-token", print_token, "print the API token (made at first start) and exit");
  app.add_flag("-v,--verbose", verbose, "log more (twice: debug)");
  CLI11_PARSE(app, argc, argv);
  ts::SetLogLevel(verbose >= 2 ? ts::LogLevel::kDebug
                  : verbose    ? ts::LogLevel::kInfo
                               : ts::LogLevel::kWarning);

  const ts::Result<ts::daemon::DaemonConfig> config = ts::daemon::LoadDaemonConfig(config_file);
  if (!config) {
    std::fprintf(stderr, "topostationd: %s\n", config.error().c_str());
    return 1;
  }
  if (print_token) {
    const ts::Result<std::string> token = ts::daemon::LoadOrCreateToken(config->token_file);
    if (!token) {
      std::fprintf(stderr, "topostationd: %s\n", token.error().c_str());
      return 1;
    }
    std::printf("%s\n", token->c_str());
    return 0;
  }
  std::signal(SIGTERM, OnSignal);
  std::signal(SIGINT, OnSignal);
  std::signal(SIGPIPE, SIG_IGN);  // a client gone mid-stream is an error of that write only
  if (ts::Status s = ts::daemon::RunDaemon(*config, g_stop); !s) {
    std::fprintf(stderr, "topostationd: %s\n", s.error().c_str());
    return 1;
  }
  return 0;
}
