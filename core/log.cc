#include "core/log.h"

#include <unistd.h>

#include <spdlog/sinks/base_sink.h>
#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace ts {
namespace {

// stderr, one line a message: "<prio>text" for the journal, "level: text" on a terminal.
class StderrSink : public spdlog::sinks::base_sink<std::mutex> {
 public:
  StderrSink() : journal_(std::getenv("JOURNAL_STREAM") != nullptr) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    const std::string text(msg.payload.data(), msg.payload.size());
    if (journal_)
      std::fprintf(stderr, "<%d>%s\n", SyslogPriority(msg.level), text.c_str());
    else
      std::fprintf(stderr, "%s: %s\n", Name(msg.level), text.c_str());
  }
  void flush_() override { std::fflush(stderr); }

 private:
  static int SyslogPriority(spdlog::level::level_enum l) {
    switch (l) {
      case spdlog::level::critical:
        return 2;
      case spdlog::level::err:
        return 3;
      case spdlog::level::warn:
        return 4;
      case spdlog::level::info:
        return 6;
      default:
        return 7;
    }
  }
  static const char* Name(spdlog::level::level_enum l) {
    switch (l) {
      case spdlog::level::critical:
      case spdlog::level::err:
        return "error";
      case spdlog::level::warn:
        return "warning";
      case spdlog::level::info:
        return "info";
      default:
        return "debug";
    }
  }
  const bool journal_;
};

std::shared_ptr<spdlog::logger> MakeLogger() {
  auto logger = std::make_shared<spdlog::logger>("topostation", std::make_shared<StderrSink>());
  logger->set_level(spdlog::level::warn);
  logger->flush_on(spdlog::level::debug);
  return logger;
}

}  // namespace

spdlog::logger& Log() {
  static const std::shared_ptr<spdlog::logger> logger = MakeLogger();
  return *logger;
}

void SetLogLevel(LogLevel level) {
  static constexpr spdlog::level::level_enum kLevels[] = {spdlog::level::debug, spdlog::level::info,
                                                          spdlog::level::warn, spdlog::level::err,
                                                          spdlog::level::off};
  Log().set_level(kLevels[static_cast<int>(level)]);
}

}  // namespace ts
