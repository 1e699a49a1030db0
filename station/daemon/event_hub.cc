#include "station/daemon/event_hub.h"

namespace ts::daemon {

using Clock = std::chrono::steady_clock;

std::string Event::Format() const {
  return "id: " + std::to_string(id) + "\nevent: " + type + "\ndata: " + data.dump() + "\n\n";
}

EventHub::EventHub() : flusher_([this] { FlushLoop(); }) {}

EventHub::~EventHub() {
  Close();
  flusher_.join();
}

void EventHub::Close() {
  std::lock_guard lock(mutex_);
  closed_ = true;
  changed_.notify_all();
}

void EventHub::PublishLocked(const std::string& type, nlohmann::json data) {
  ring_.push_back({next_id_++, type, std::move(data)});
  if (ring_.size() > kRingSize) ring_.pop_front();
  changed_.notify_all();
}

void EventHub::Publish(const std::string& type, nlohmann::json data) {
  std::lock_guard lock(mutex_);
  PublishLocked(type, std::move(data));
}

void EventHub::PublishThrottled(const std::string& key, const std::string& type,
                                nlohmann::json data) {
  std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  auto last = last_sent_.find(key);
  if (last == last_sent_.end() || now - last->second >= kMinInterval) {
    last_sent_[key] = now;
    held_.erase(key);
    PublishLocked(type, std::move(data));
    return;
  }
  held_[key] = {type, std::move(data)};
}

void EventHub::FlushLoop() {
  std::unique_lock lock(mutex_);
  while (!closed_) {
    changed_.wait_for(lock, kMinInterval / 5);
    const auto now = Clock::now();
    for (auto it = held_.begin(); it != held_.end();) {
      if (now - last_sent_[it->first] < kMinInterval) {
        ++it;
        continue;
      }
      last_sent_[it->first] = now;
      PublishLocked(it->second.type, std::move(it->second.data));
      it = held_.erase(it);
    }
  }
}

uint64_t EventHub::last_id() const {
  std::lock_guard lock(mutex_);
  return next_id_ - 1;
}

std::vector<Event> EventHub::WaitAfter(uint64_t after_id, std::chrono::milliseconds wait,
                                       bool* missed) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, wait, [&] { return closed_ || next_id_ - 1 > after_id; });
  std::vector<Event> out;
  if (closed_) return out;
  if (missed) *missed = !ring_.empty() && ring_.front().id > after_id + 1;
  for (const Event& e : ring_)
    if (e.id > after_id) out.push_back(e);
  return out;
}

}  // namespace ts::daemon
