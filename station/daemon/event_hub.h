#pragma once
// The daemon's events, for GET /events (server-sent events): each event has an id, a type and
// JSON data. Progress of one kind ("job", "stage") is sent at most twice a second: a newer
// one replaces the one still held back, which goes out when its half second is over. A
// client that reconnects with Last-Event-ID gets what it missed, as far as the ring reaches.
// Thread-safe.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace ts::daemon {

struct Event {
  uint64_t id = 0;
  std::string type;  // "snapshot", "job", "device", "log", ...
  nlohmann::json data;
  std::string Format() const;  // "id: N\nevent: TYPE\ndata: JSON\n\n"
};

class EventHub {
 public:
  static constexpr std::chrono::milliseconds kMinInterval{500};  // 2 Hz per throttled kind
  static constexpr size_t kRingSize = 512;

  EventHub();
  ~EventHub();

  void Publish(const std::string& type, nlohmann::json data);
  // At most 2 Hz per `key`; the latest data wins.
  void PublishThrottled(const std::string& key, const std::string& type, nlohmann::json data);

  uint64_t last_id() const;
  // Events after `after_id`, waiting up to `wait` for one; empty on timeout or Close().
  // `*missed` is set when the ring no longer holds all of them.
  std::vector<Event> WaitAfter(uint64_t after_id, std::chrono::milliseconds wait,
                               bool* missed = nullptr);
  // Wakes every waiter for good (the daemon stops).
  void Close();

 private:
  void PublishLocked(const std::string& type, nlohmann::json data);
  void FlushLoop();
  struct Held {
    std::string type;
    nlohmann::json data;
  };
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Event> ring_;
  uint64_t next_id_ = 1;
  bool closed_ = false;
  std::map<std::string, std::chrono::steady_clock::time_point> last_sent_;
  std::map<std::string, Held> held_;
  std::thread flusher_;
};

}  // namespace ts::daemon
