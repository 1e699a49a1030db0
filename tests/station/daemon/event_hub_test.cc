#include "station/daemon/event_hub.h"

#include <gtest/gtest.h>

#include <thread>

namespace ts::daemon {
namespace {

using namespace std::chrono_literals;

TEST(EventHub, EventsCarryIncreasingIdsAndTheServerSentEventFormat) {
  EventHub hub;
  hub.Publish("devices", {{"stage", "present"}});
  hub.Publish("log", {{"message", "x"}});
  const std::vector<Event> events = hub.WaitAfter(0, 0ms);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].id, 1u);
  EXPECT_EQ(events[1].id, 2u);
  EXPECT_EQ(events[0].Format(), "id: 1\nevent: devices\ndata: {\"stage\":\"present\"}\n\n");
  EXPECT_EQ(hub.WaitAfter(1, 0ms).size(), 1u);
}

TEST(EventHub, ProgressGoesOutAtMostTwiceASecondAndTheLatestArrives) {
  EventHub hub;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i <= 100; ++i) {
    hub.PublishThrottled("job", "progress", {{"pair", i}});
    std::this_thread::sleep_for(10ms);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::this_thread::sleep_for(700ms);  // the one held back goes out
  const std::vector<Event> events = hub.WaitAfter(0, 0ms);
  ASSERT_FALSE(events.empty());
  EXPECT_LE(events.size(), static_cast<size_t>(seconds / 0.5) + 2);
  EXPECT_GE(events.size(), 2u);
  EXPECT_EQ(events.back().data["pair"], 100);
  for (size_t i = 1; i < events.size(); ++i)
    EXPECT_LT(events[i - 1].data["pair"], events[i].data["pair"]);
}

TEST(EventHub, AWaiterWakesForANewEventAndAReconnectLearnsWhatItMissed) {
  EventHub hub;
  std::thread late([&] {
    std::this_thread::sleep_for(100ms);
    hub.Publish("job", {{"id", 1}});
  });
  const std::vector<Event> got = hub.WaitAfter(0, 5000ms);
  late.join();
  ASSERT_EQ(got.size(), 1u);
  for (size_t i = 0; i < EventHub::kRingSize + 10; ++i) hub.Publish("log", {{"i", i}});
  bool missed = false;
  const std::vector<Event> after = hub.WaitAfter(1, 0ms, &missed);
  EXPECT_TRUE(missed);
  EXPECT_EQ(after.size(), EventHub::kRingSize);
  hub.WaitAfter(hub.last_id(), 0ms, &missed);
  EXPECT_FALSE(missed);
}

TEST(EventHub, CloseWakesEveryWaiter) {
  EventHub hub;
  std::thread closer([&] {
    std::this_thread::sleep_for(100ms);
    hub.Close();
  });
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(hub.WaitAfter(0, 10000ms).empty());
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5000ms);
  closer.join();
}

}  // namespace
}  // namespace ts::daemon
