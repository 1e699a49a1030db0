#include "devices/usb_watcher.h"

#include <gtest/gtest.h>

namespace ts {
namespace {

TEST(UsbWatcher, ParsesVidPidAndSerial) {
  const Result<UsbMatch> a = ParseUsbMatch("stage", "0403:6001");
  ASSERT_TRUE(a.ok()) << a.error();
  EXPECT_EQ(a->vendor_id, 0x0403);
  EXPECT_EQ(a->product_id, 0x6001);
  EXPECT_EQ(a->serial, "");
  const Result<UsbMatch> b = ParseUsbMatch("left camera", "2676:BA02:23456789");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b->product_id, 0xba02);
  EXPECT_EQ(b->serial, "23456789");
  EXPECT_NE(ParseUsbMatch("stage", "0403").error().find("must be VID:PID[:SERIAL]"),
            std::string::npos);
  EXPECT_NE(ParseUsbMatch("stage", "403:6001").error().find("'403' in '403:6001'"),
            std::string::npos);
  EXPECT_NE(ParseUsbMatch("stage", "04g3:6001").error().find("not a 4-digit hex"),
            std::string::npos);
}

// With no such device on the bus the watcher runs and reports it absent; it stops cleanly.
TEST(UsbWatcher, RunsAndReportsAnAbsentDevice) {
  int events = 0;
  auto watcher =
      UsbWatcher::Start({*ParseUsbMatch("stage", "dead:beef")}, [&](const UsbEvent&) { ++events; });
  ASSERT_TRUE(watcher.ok()) << watcher.error();
  EXPECT_FALSE((*watcher)->Present("stage"));
  EXPECT_FALSE((*watcher)->Present("no such name"));
  watcher->reset();
  EXPECT_EQ(events, 0);
}

}  // namespace
}  // namespace ts
