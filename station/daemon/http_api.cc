#include "station/daemon/http_api.h"

#include <sys/statvfs.h>

#include <fstream>

#include "core/log.h"
#include "core/version.h"
#include "station/daemon/http_responses.h"

namespace ts::daemon {
namespace {

// "host", "host:8080", "[::1]:8080" -> the host alone.
std::string HostWithoutPort(const std::string& value) {
  if (!value.empty() && value.front() == '[') {
    const size_t close = value.find(']');
    return close == std::string::npos ? value : value.substr(0, close + 1);
  }
  const size_t colon = value.rfind(':');
  return colon == std::string::npos ? value : value.substr(0, colon);
}

// "http://host:port" -> host; "" for what is not an http(s) origin.
std::string OriginHost(const std::string& origin) {
  for (const char* scheme : {"http://", "https://"})
    if (origin.rfind(scheme, 0) == 0) return HostWithoutPort(origin.substr(std::strlen(scheme)));
  return "";
}

std::optional<int64_t> JobId(const httplib::Request& req) {
  try {
    return std::stoll(req.matches[1].str());
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

void SendJobResult(httplib::Response& res, const std::variant<Job, JobError>& r, int ok_status) {
  if (const JobError* e = std::get_if<JobError>(&r))
    return SendError(res, e->http_status, e->message);
  SendJson(res, ok_status, std::get<Job>(r).ToJson());
}

uint64_t DiskFreeBytes(const std::string& dir) {
  struct statvfs s {};
  if (::statvfs(dir.c_str(), &s) != 0) return 0;
  return static_cast<uint64_t>(s.f_bavail) * s.f_frsize;
}

}  // namespace

void SendJson(httplib::Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void SendError(httplib::Response& res, int status, const std::string& message) {
  SendJson(res, status, {{"error", message}});
}

void SendFile(httplib::Response& res, const std::string& path, const char* content_type) {
  auto file = std::make_shared<std::ifstream>(path, std::ios::binary);
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec || !*file) return SendError(res, 404, "no such file");
  res.set_content_provider(
      size, content_type, [file](size_t offset, size_t length, httplib::DataSink& sink) {
        std::vector<char> buffer(std::min<size_t>(length, 1 << 16));
        file->seekg(static_cast<std::streamoff>(offset));
        file->read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        return file->gcount() > 0 && sink.write(buffer.data(), static_cast<size_t>(file->gcount()));
      });
}

HttpApi::HttpApi(ApiParts parts)
    : parts_(std::move(parts)),
      catalog_(parts_.config->stations_dir),
      preview_(parts_.devices, parts_.jobs) {
  hosts_ = {"localhost", "127.0.0.1", "[::1]", parts_.config->listen_address};
  hosts_.insert(parts_.config->allowed_hosts.begin(), parts_.config->allowed_hosts.end());
  server_.new_task_queue = [] { return new httplib::ThreadPool(kMaxEventStreams + kOtherThreads); };
  server_.set_payload_max_length(kMaxBodyBytes);
  server_.set_read_timeout(10, 0);  // a client that stalls mid-request is dropped
  server_.set_write_timeout(10, 0);
  // One request per connection: a kept-alive connection holds a server thread while it idles,
  // and fifty pages polling once a second would hold them all.
  server_.set_keep_alive_max_count(1);
  server_.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    return Allowed(req, res) ? httplib::Server::HandlerResponse::Unhandled
                             : httplib::Server::HandlerResponse::Handled;
  });
  Routes();
  PageRoutes();
}

HttpApi::~HttpApi() { Stop(); }

bool HttpApi::Bind(std::string* why) {
  if (!server_.bind_to_port(parts_.config->listen_address, parts_.config->listen_port)) {
    *why = "cannot listen on " + parts_.config->listen_address + ":" +
           std::to_string(parts_.config->listen_port) + " (in use, or not an address of this host)";
    return false;
  }
  port_ = parts_.config->listen_port;
  return true;
}

void HttpApi::Serve() { server_.listen_after_bind(); }

void HttpApi::Stop() {
  stopping_ = true;
  server_.stop();
}

bool HttpApi::Allowed(const httplib::Request& req, httplib::Response& res) {
  if (!hosts_.count(HostWithoutPort(req.get_header_value("Host")))) {
    SendError(res, 403, "Host '" + req.get_header_value("Host") + "' is not a name of this daemon");
    return false;
  }
  if (req.method == "GET" || req.method == "HEAD") return true;
  if (req.has_header("Origin") && !hosts_.count(OriginHost(req.get_header_value("Origin")))) {
    SendError(res, 403, "Origin '" + req.get_header_value("Origin") + "' may not write here");
    return false;
  }
  return Authorized(req, res);
}

bool HttpApi::Authorized(const httplib::Request& req, httplib::Response& res) {
  const std::string& client = req.remote_addr;  // the connection's, never a header's
  if (const int wait = throttle_.WaitSeconds(client); wait > 0) {
    res.set_header("Retry-After", std::to_string(wait));
    SendError(res, 429, "too many wrong tokens: wait " + std::to_string(wait) + " s");
    return false;
  }
  const std::string header = req.get_header_value("Authorization");
  const std::string prefix = "Bearer ";
  if (header.rfind(prefix, 0) == 0 && TokenMatches(header.substr(prefix.size()), parts_.token)) {
    throttle_.Succeeded(client);
    return true;
  }
  throttle_.Failed(client);
  res.set_header("WWW-Authenticate", "Bearer");
  SendError(res, 401,
            header.empty() ? "this needs the token (Authorization: Bearer ...; "
                             "topostationd --print-token)"
                           : "wrong token");
  return false;
}

nlohmann::json HttpApi::StatusJson() const {
  const std::string not_ready = parts_.devices->WhyNotReady();
  return {{"version", SoftwareVersion()},
          {"devices", parts_.devices->DevicesJson()},
          {"ready", not_ready.empty()},
          {"not_ready_because", not_ready},
          {"stage", parts_.devices->stage_reading().ToJson()},
          {"disk_free_bytes", DiskFreeBytes(parts_.config->stations_dir)},
          {"current_job", parts_.jobs->CurrentJob()}};
}

void HttpApi::Routes() {
  const std::string api = "/api/v1";
  server_.Get(api + "/health", [](const httplib::Request&, httplib::Response& res) {
    SendJson(res, 200, {{"ok", true}, {"version", SoftwareVersion()}});
  });
  server_.Get(api + "/status", [this](const httplib::Request&, httplib::Response& res) {
    SendJson(res, 200, StatusJson());
  });
  server_.Get(api + "/events",
              [this](const httplib::Request& req, httplib::Response& res) { Events(req, res); });
  server_.Post(api + "/jobs",
               [this](const httplib::Request& req, httplib::Response& res) { PostJob(req, res); });
  server_.Get(api + "/jobs", [this](const httplib::Request&, httplib::Response& res) {
    nlohmann::json list = nlohmann::json::array();
    for (const Job& j : parts_.store->List()) list.push_back(j.ToJson());
    SendJson(res, 200, list);
  });
  server_.Get(api + R"(/jobs/(\d{1,18}))",
              [this](const httplib::Request& req, httplib::Response& res) {
                const std::optional<int64_t> id = JobId(req);
                Result<Job> job = id ? parts_.store->Get(*id) : Error{"no such job"};
                if (!job) return SendError(res, 404, job.error());
                SendJson(res, 200, job->ToJson());
              });
  server_.Post(api + R"(/jobs/(\d{1,18})/(cancel|resume))",
               [this](const httplib::Request& req, httplib::Response& res) {
                 const std::optional<int64_t> id = JobId(req);
                 if (!id) return SendError(res, 404, "no such job");
                 if (req.matches[2] == "cancel")
                   return SendJobResult(res, parts_.jobs->Cancel(*id), 200);
                 SendJobResult(res, parts_.jobs->Resume(*id), 200);
               });
  server_.Get(api + "/stations", [this](const httplib::Request&, httplib::Response& res) {
    SendJson(res, 200, catalog_.List());
  });
  server_.Get(api + R"(/stations/([^/]+))",
              [this](const httplib::Request& req, httplib::Response& res) {
                const std::optional<nlohmann::json> s = catalog_.Get(req.matches[1]);
                if (!s) return SendError(res, 404, "no such station");
                SendJson(res, 200, *s);
              });
  server_.Get(api + R"(/stations/([^/]+)/products/([^/]+))",
              [this](const httplib::Request& req, httplib::Response& res) { Product(req, res); });
  server_.Post(api + R"(/stage/(home|move|stop))",
               [this](const httplib::Request& req, httplib::Response& res) {
                 StageCommand(req.matches[1], req, res);
               });
  server_.Get(api + R"(/cameras/(left|right)/snapshot\.jpg)", [this](const httplib::Request& req,
                                                                     httplib::Response& res) {
    const Side side = req.matches[1] == "left" ? Side::kLeft : Side::kRight;
    Result<std::vector<unsigned char>> jpeg = preview_.Snapshot(side);
    if (!jpeg) return SendError(res, 409, jpeg.error());
    res.set_header("Cache-Control", "no-store");
    res.set_content(reinterpret_cast<const char*>(jpeg->data()), jpeg->size(), "image/jpeg");
  });
}

void HttpApi::PostJob(const httplib::Request& req, httplib::Response& res) {
  const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
  if (body.is_discarded()) return SendError(res, 400, "the body is not JSON");
  Result<JobRequest> request = ParseJobRequest(body);
  if (!request) return SendError(res, 400, request.error());
  const std::string key = req.get_header_value("Idempotency-Key");
  if (key.size() > 200) return SendError(res, 400, "Idempotency-Key: at most 200 characters");
  bool existed = false;
  const auto r = parts_.jobs->Submit(*request, key, &existed);
  SendJobResult(res, r, existed ? 200 : 201);
}

void HttpApi::Product(const httplib::Request& req, httplib::Response& res) {
  const std::string name = req.matches[2];
  const std::optional<std::string> path = catalog_.ProductPath(req.matches[1], name);
  if (!path) return SendError(res, 404, "no such product");
  SendFile(res, *path, ContentTypeOf(name));
}

void HttpApi::StageCommand(const std::string& command, const httplib::Request& req,
                           httplib::Response& res) {
  if (command == "stop") {
    if (Status s = parts_.devices->StopStage(); !s) return SendError(res, 409, s.error());
    return SendJson(res, 200, {{"stopped", true}});
  }
  StagePose target;
  if (command == "move") {
    const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
    if (!body.is_object() || !body.contains("pan_deg") || !body.contains("tilt_deg") ||
        !body["pan_deg"].is_number() || !body["tilt_deg"].is_number())
      return SendError(res, 400, "the body must be {\"pan_deg\": N, \"tilt_deg\": N}");
    target = {body["pan_deg"].get<double>(), body["tilt_deg"].get<double>()};
    if (!(std::abs(target.pan_deg) <= 360.0) || !(std::abs(target.tilt_deg) <= 32.0))
      return SendError(res, 400, "pan_deg must be within +-360 and tilt_deg within +-32");
  }
  std::string holder;
  std::unique_ptr<RigLease> lease = parts_.devices->TryLease("a stage " + command, &holder,
                                                             DeviceSupervisor::LeaseKind::kCommand);
  if (!lease) return SendError(res, 409, "the rig is in use: " + holder);
  Result<Stage*> stage = lease->stage();
  if (!stage) return SendError(res, 409, stage.error());
  const CaptureOptions timeouts;
  Result<StagePose> at = StagePose{0.0, 0.0};
  if (command == "home") {
    if (Status s = (*stage)->Home(timeouts.home_timeout); !s) at = Error{s.error()};
  } else {
    at = (*stage)->MoveTo(target, timeouts.position_tolerance_deg, timeouts.move_timeout);
  }
  if (!at) return SendError(res, 409, at.error());
  SendJson(res, 200, {{"pan_deg", at->pan_deg}, {"tilt_deg", at->tilt_deg}});
}

void HttpApi::Events(const httplib::Request& req, httplib::Response& res) {
  if (++streams_ > kMaxEventStreams) {
    --streams_;
    res.set_header("Retry-After", "5");
    return SendError(res, 503, "at most 8 event streams at once");
  }
  uint64_t after = parts_.events->last_id();
  std::string first = Event{after, "snapshot", {{"status", StatusJson()}}}.Format();
  if (req.has_header("Last-Event-ID")) {  // a reconnect: what it missed, when the ring has it
    try {
      after = std::stoull(req.get_header_value("Last-Event-ID"));
      first.clear();
    } catch (const std::exception&) {
    }
  }
  res.set_header("Cache-Control", "no-store");
  res.set_chunked_content_provider(
      "text/event-stream",
      [this, after, first](size_t, httplib::DataSink& sink) mutable {
        if (!first.empty()) {
          if (!sink.write(first.data(), first.size())) return false;
          first.clear();
          return true;
        }
        bool missed = false;
        const std::vector<Event> events = parts_.events->WaitAfter(after, kHeartbeat, &missed);
        if (stopping_) return false;
        std::string text;
        if (missed) text += Event{after, "snapshot", {{"status", StatusJson()}}}.Format();
        for (const Event& e : events) text += e.Format();
        if (!events.empty()) after = events.back().id;
        if (text.empty()) text = ": heartbeat\n\n";
        return sink.write(text.data(), text.size());
      },
      [this](bool) { --streams_; });
}

}  // namespace ts::daemon
