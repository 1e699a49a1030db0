#include "devices/usb_watcher.h"

#include <libusb-1.0/libusb.h>

#include <sstream>

namespace ts {

Result<UsbMatch> ParseUsbMatch(const std::string& name, const std::string& spec) {
  std::vector<std::string> parts;
  std::stringstream in(spec);
  for (std::string part; std::getline(in, part, ':');) parts.push_back(part);
  if (parts.size() < 2 || parts.size() > 3)
    return Error{name + ": '" + spec + "' must be VID:PID[:SERIAL]"};
  UsbMatch m;
  m.name = name;
  uint16_t* ids[2] = {&m.vendor_id, &m.product_id};
  for (int i = 0; i < 2; ++i) {
    if (parts[i].size() != 4 ||
        parts[i].find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
      return Error{name + ": '" + parts[i] + "' in '" + spec + "' is not a 4-digit hex USB id"};
    *ids[i] = static_cast<uint16_t>(std::stoul(parts[i], nullptr, 16));
  }
  if (parts.size() == 3) m.serial = parts[2];
  return m;
}

namespace {

int HotplugCallback(libusb_context*, libusb_device* device, libusb_hotplug_event event,
                    void* self) {
  static_cast<UsbWatcher*>(self)->OnHotplug(device, event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED);
  return 0;  // stay registered
}

// The serial number needs the device opened, which may not be permitted: empty then.
std::string SerialOf(libusb_device* device, const libusb_device_descriptor& d) {
  if (d.iSerialNumber == 0) return "";
  libusb_device_handle* handle = nullptr;
  if (libusb_open(device, &handle) != 0) return "";
  unsigned char text[256] = {};
  const int n = libusb_get_string_descriptor_ascii(handle, d.iSerialNumber, text, sizeof(text));
  libusb_close(handle);
  return n > 0 ? std::string(reinterpret_cast<char*>(text), static_cast<size_t>(n)) : "";
}

}  // namespace

void UsbWatcher::OnHotplug(void* device_ptr, bool arrived) {
  auto* device = static_cast<libusb_device*>(device_ptr);
  libusb_device_descriptor d;
  if (libusb_get_device_descriptor(device, &d) != 0) return;
  // On departure the device can no longer be opened: match on ids alone.
  const std::string serial = arrived ? SerialOf(device, d) : "";
  for (const UsbMatch& m : matches_) {
    if (m.vendor_id != d.idVendor || m.product_id != d.idProduct) continue;
    if (arrived && !m.serial.empty() && !serial.empty() && serial != m.serial) continue;
    {
      std::lock_guard lock(mutex_);
      int& count = present_[m.name];
      count = arrived ? count + 1 : std::max(0, count - 1);
    }
    if (on_event_)
      on_event_({m.name, arrived, d.idVendor, d.idProduct, libusb_get_bus_number(device),
                 libusb_get_device_address(device)});
  }
}

bool UsbWatcher::Present(const std::string& name) const {
  std::lock_guard lock(mutex_);
  const auto it = present_.find(name);
  return it != present_.end() && it->second > 0;
}

Result<std::unique_ptr<UsbWatcher>> UsbWatcher::Start(
    std::vector<UsbMatch> matches, std::function<void(const UsbEvent&)> on_event) {
  std::unique_ptr<UsbWatcher> w(new UsbWatcher());
  w->matches_ = std::move(matches);
  w->on_event_ = std::move(on_event);
  if (const int rc = libusb_init(&w->context_); rc != 0)
    return Error{std::string("USB watcher: libusb_init failed: ") + libusb_error_name(rc)};
  if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG))
    return Error{"USB watcher: this libusb has no hotplug support"};
  for (const UsbMatch& m : w->matches_) {
    libusb_hotplug_callback_handle handle;
    const int rc = libusb_hotplug_register_callback(
        w->context_,
        static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                          LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
        LIBUSB_HOTPLUG_ENUMERATE, m.vendor_id, m.product_id, LIBUSB_HOTPLUG_MATCH_ANY,
        HotplugCallback, w.get(), &handle);
    if (rc != LIBUSB_SUCCESS)
      return Error{"USB watcher: cannot watch " + m.name + ": " + libusb_error_name(rc)};
    w->handles_.push_back(handle);
  }
  UsbWatcher* self = w.get();
  w->thread_ = std::thread([self] {
    while (!self->stop_) {
      timeval tv{0, 200000};
      libusb_handle_events_timeout_completed(self->context_, &tv, nullptr);
    }
  });
  return w;
}

UsbWatcher::~UsbWatcher() {
  stop_ = true;
  if (context_) {
    for (int handle : handles_) libusb_hotplug_deregister_callback(context_, handle);
  }
  if (thread_.joinable()) thread_.join();
  if (context_) libusb_exit(context_);
}

Result<std::vector<UsbDeviceInfo>> ListUsbDevices() {
  libusb_context* ctx = nullptr;
  if (const int rc = libusb_init(&ctx); rc != 0)
    return Error{std::string("USB: cannot initialise libusb: ") + libusb_error_name(rc)};
  libusb_device** devices = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &devices);
  std::vector<UsbDeviceInfo> list;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d;
    if (libusb_get_device_descriptor(devices[i], &d) != 0) continue;
    list.push_back({d.idVendor, d.idProduct, libusb_get_bus_number(devices[i]),
                    libusb_get_device_address(devices[i])});
  }
  if (n >= 0) libusb_free_device_list(devices, 1);
  libusb_exit(ctx);
  if (n < 0)
    return Error{std::string("USB: cannot list devices: ") +
                 libusb_error_name(static_cast<int>(n))};
  return list;
}

}  // namespace ts
