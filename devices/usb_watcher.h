#pragma once
// Presence of the rig's USB devices (USB3 Vision cameras, the stage's USB-serial adapter),
// watched with libusb hotplug, as arrival and departure events for the daemon. GigE Vision
// cameras are not USB: their presence comes from Aravis discovery.
//
// Threads: events are delivered on the watcher's own thread; Present() may be called from any.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/result.h"

struct libusb_context;

namespace ts {

struct UsbMatch {
  std::string name;  // what the rig calls it: "stage", "left camera"
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  std::string serial;  // empty: any serial
};

// "0403:6001" or "0403:6001:FT12345" (hex ids); error names the part that is wrong.
Result<UsbMatch> ParseUsbMatch(const std::string& name, const std::string& spec);

// Every USB device on the buses now (for `topostation devices`), in libusb's order.
struct UsbDeviceInfo {
  uint16_t vendor_id = 0, product_id = 0;
  int bus = 0, address = 0;
};
Result<std::vector<UsbDeviceInfo>> ListUsbDevices();

struct UsbEvent {
  std::string name;  // the match's name
  bool arrived = true;
  uint16_t vendor_id = 0, product_id = 0;
  int bus = 0, address = 0;
};

class UsbWatcher {
 public:
  static Result<std::unique_ptr<UsbWatcher>> Start(std::vector<UsbMatch> matches,
                                                   std::function<void(const UsbEvent&)> on_event);
  ~UsbWatcher();
  bool Present(const std::string& name) const;

  // libusb's hotplug callback lands here (on the watcher thread).
  void OnHotplug(void* device, bool arrived);

 private:
  UsbWatcher() = default;
  libusb_context* context_ = nullptr;
  std::vector<UsbMatch> matches_;
  std::vector<int> handles_;
  std::function<void(const UsbEvent&)> on_event_;
  mutable std::mutex mutex_;
  std::map<std::string, int> present_;  // name -> devices present
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ts
