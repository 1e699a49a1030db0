#pragma once
// The daemon's HTTP API under /api/v1 (DESIGN.md "Daemon"), on cpp-httplib. Reads need no
// token (the page's EventSource and <img> cannot send one); everything that moves hardware or
// writes needs `Authorization: Bearer TOKEN`. Every request's Host must be one of the
// configured names (DNS rebinding), a POST's Origin, when sent, one of them too; no CORS
// headers; bodies over 64 KiB get 413; at most kMaxEventStreams event streams, each holding
// one server thread, so the pool has that many threads more than the other requests need.
#include <atomic>
#include <memory>
#include <set>
#include <string>

#include "station/daemon/access_token.h"
#include "station/daemon/camera_preview.h"
#include "station/daemon/daemon_config.h"
#include "station/daemon/device_supervisor.h"
#include "station/daemon/event_hub.h"
#include "station/daemon/job_runner.h"
#include "station/daemon/job_store.h"
#include "station/daemon/station_catalog.h"

// After Eigen: httplib brings <resolv.h>, whose `_res` macro breaks Eigen's products.
#include <httplib.h>  // NOLINT(build/include_order)

namespace ts::daemon {

struct ApiParts {
  const DaemonConfig* config;
  std::string token;
  JobStore* store;
  DeviceSupervisor* devices;
  EventHub* events;
  JobRunner* jobs;
};

class HttpApi {
 public:
  static constexpr size_t kMaxBodyBytes = 64 * 1024;
  static constexpr int kMaxEventStreams = 8;
  static constexpr int kOtherThreads = 8;
  static constexpr std::chrono::seconds kHeartbeat{15};

  explicit HttpApi(ApiParts parts);
  ~HttpApi();
  // Binds the configured address; false with `*why` when it cannot.
  bool Bind(std::string* why);
  void Serve();  // blocks until Stop()
  void Stop();
  int port() const { return port_; }
  nlohmann::json StatusJson() const;  // GET /status

 private:
  void Routes();
  bool Allowed(const httplib::Request& req, httplib::Response& res);
  bool Authorized(const httplib::Request& req, httplib::Response& res);
  void Events(const httplib::Request& req, httplib::Response& res);
  void PostJob(const httplib::Request& req, httplib::Response& res);
  void StageCommand(const std::string& command, const httplib::Request& req,
                    httplib::Response& res);
  void Product(const httplib::Request& req, httplib::Response& res);
  // The operator's page and what it needs beyond the API above (http_api_page.cc): its files,
  // pair thumbnails, a station's zip, the campaign table, the comparison of two epochs.
  void PageRoutes();
  void PairThumbnail(const httplib::Request& req, httplib::Response& res);
  void StationZip(const httplib::Request& req, httplib::Response& res);
  void CampaignTable(bool geopackage, httplib::Response& res);
  void PostDiff(const httplib::Request& req, httplib::Response& res);

  ApiParts parts_;
  StationCatalog catalog_;
  CameraPreview preview_;
  AuthThrottle throttle_;
  std::set<std::string> hosts_;
  httplib::Server server_;
  std::atomic<int> streams_{0};
  std::atomic<bool> stopping_{false};
  int port_ = 0;
};

}  // namespace ts::daemon
