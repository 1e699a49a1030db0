// topostation devices: the cameras Aravis discovers, the USB devices and the serial ports.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "core/log.h"
#include "devices/aravis_camera.h"
#include "devices/usb_watcher.h"
#include "station/commands.h"

namespace ts {
namespace {

nlohmann::json UsbDevices() {
  nlohmann::json list = nlohmann::json::array();
  const Result<std::vector<UsbDeviceInfo>> devices = ListUsbDevices();
  if (!devices) {
    Log().warn("{}", devices.error());
    return list;
  }
  for (const UsbDeviceInfo& d : *devices) {
    char id[16];
    std::snprintf(id, sizeof(id), "%04x:%04x", d.vendor_id, d.product_id);
    list.push_back({{"vid_pid", id}, {"bus", d.bus}, {"address", d.address}});
  }
  return list;
}

nlohmann::json SerialPorts() {
  nlohmann::json list = nlohmann::json::array();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("ttyUSB") || name.starts_with("ttyACM") || name == "topostation-stage")
      list.push_back(entry.path().string());
  }
  for (const auto& entry : std::filesystem::directory_iterator("/dev/serial/by-id", ec))
    list.push_back(entry.path().string());
  return list;
}

}  // namespace

void AddDevicesCommand(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd =
      app.add_subcommand("devices", "List cameras (Aravis discovery), USB devices, serial ports");
  cmd->add_flag("--json", *json, "print JSON");
  cmd->callback([json] {
    nlohmann::json cameras = nlohmann::json::array();
    for (const CameraInfo& c : ListAravisCameras())
      cameras.push_back({{"id", c.id},
                         {"serial", c.serial},
                         {"address", c.address},
                         {"vendor", c.vendor},
                         {"model", c.model},
                         {"protocol", c.protocol}});
    const nlohmann::json all = {
        {"cameras", cameras}, {"usb", UsbDevices()}, {"serial_ports", SerialPorts()}};
    if (*json) {
      std::printf("%s\n", all.dump(2).c_str());
      return;
    }
    std::printf("cameras (%zu):\n", all["cameras"].size());
    for (const auto& c : all["cameras"])
      std::printf("  %-24s serial %-12s %-16s %s %s\n", c["id"].get<std::string>().c_str(),
                  c["serial"].get<std::string>().c_str(), c["address"].get<std::string>().c_str(),
                  c["vendor"].get<std::string>().c_str(), c["model"].get<std::string>().c_str());
    std::printf("USB devices (%zu):\n", all["usb"].size());
    for (const auto& u : all["usb"])
      std::printf("  %s on bus %d address %d\n", u["vid_pid"].get<std::string>().c_str(),
                  u["bus"].get<int>(), u["address"].get<int>());
    std::printf("serial ports (%zu):\n", all["serial_ports"].size());
    for (const auto& p : all["serial_ports"]) std::printf("  %s\n", p.get<std::string>().c_str());
  });
}

}  // namespace ts
