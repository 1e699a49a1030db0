#pragma once
// The daemon's bearer token: 256 random bits, created at first start in a file only its owner
// may read, compared in constant time; and a throttle that slows down a client that keeps
// guessing.
#include <chrono>
#include <map>
#include <mutex>
#include <string>

#include "core/result.h"

namespace ts::daemon {

// Reads the token from `file`, or creates it (64 hex digits, mode 0600) when there is none.
// A token file that others may read is refused, naming the file and its mode.
Result<std::string> LoadOrCreateToken(const std::string& file);

// Constant time in the length of `expected`.
bool TokenMatches(const std::string& presented, const std::string& expected);

// After kFreeFailures wrong tokens from one address, that address is refused for a wait that
// doubles with each further failure (1 s, 2 s, ... 60 s); a right token clears its record.
class AuthThrottle {
 public:
  static constexpr int kFreeFailures = 5;
  static constexpr size_t kMaxRecords = 10000;
  using Clock = std::chrono::steady_clock;
  // The seconds the address must still wait (0: it may try now).
  int WaitSeconds(const std::string& address, Clock::time_point now = Clock::now());
  void Failed(const std::string& address, Clock::time_point now = Clock::now());
  void Succeeded(const std::string& address);

 private:
  struct Record {
    int failures = 0;
    Clock::time_point blocked_until{};
  };
  std::mutex mutex_;
  std::map<std::string, Record> records_;
};

}  // namespace ts::daemon
