// The operator's page (web/, built in) and the routes only it needs. The page's own files
// are served with a content security policy that allows nothing from elsewhere.
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "processing/io/atomic_file.h"
#include "station/campaign.h"
#include "station/commands.h"
#include "station/daemon/daemon_config.h"
#include "station/daemon/http_api.h"
#include "station/daemon/http_responses.h"
#include "station/daemon/web_assets.h"
#include "station/diff_products.h"
#include "station/station_archive.h"

namespace ts::daemon {
namespace {

namespace fs = std::filesystem;

constexpr int kThumbnailWidth = 240;
// A diff's folder under STATE/diffs: BEFORE--AFTER, two station ids.
constexpr const char* kDiffId = "[A-Za-z0-9_-]{1,64}--[A-Za-z0-9_-]{1,64}";

}  // namespace

void HttpApi::PageRoutes() {
  for (const WebFile& file : kWebFiles) {
    auto serve = [&file](const httplib::Request&, httplib::Response& res) {
      res.set_header("Content-Security-Policy",
                     "default-src 'self'; img-src 'self'; object-src 'none'; "
                     "frame-ancestors 'none'; base-uri 'none'");
      res.set_header("X-Content-Type-Options", "nosniff");
      res.set_header("Cache-Control", "no-cache");
      res.set_content(file.body.data(), file.body.size(), WebContentType(file.path));
    };
    server_.Get(std::string(file.path), serve);
    if (file.path == "/index.html") server_.Get("/", serve);
  }
  const std::string api = "/api/v1";
  server_.Get(
      api + R"(/stations/([^/]+)/pairs/(\d{1,3})/(left|right)\.jpg)",
      [this](const httplib::Request& req, httplib::Response& res) { PairThumbnail(req, res); });
  server_.Get(
      api + R"(/stations/([^/]+)/station\.zip)",
      [this](const httplib::Request& req, httplib::Response& res) { StationZip(req, res); });
  server_.Get(api + R"(/campaign\.(csv|gpkg))",
              [this](const httplib::Request& req, httplib::Response& res) {
                CampaignTable(req.matches[1] == "gpkg", res);
              });
  server_.Post(api + "/diffs",
               [this](const httplib::Request& req, httplib::Response& res) { PostDiff(req, res); });
  server_.Get(api + "/diffs/(" + kDiffId +
                  R"()/(dod\.png|dod\.tif|dod_std\.tif|change\.json|subsidence\.geojson))",
              [this](const httplib::Request& req, httplib::Response& res) {
                const fs::path file = fs::path(parts_.config->state_dir) / "diffs" /
                                      req.matches[1].str() / req.matches[2].str();
                if (!fs::is_regular_file(file)) return SendError(res, 404, "no such comparison");
                SendFile(res, file.string(), ContentTypeOf(req.matches[2].str()));
              });
}

void HttpApi::PairThumbnail(const httplib::Request& req, httplib::Response& res) {
  const Side side = req.matches[3] == "left" ? Side::kLeft : Side::kRight;
  const std::optional<std::string> path =
      catalog_.PairImagePath(req.matches[1], std::stoi(req.matches[2].str()), side);
  if (!path) return SendError(res, 404, "no such pair");
  // A quarter of the image decoded (libpng reduces while reading), 8 bit whatever the format.
  const cv::Mat quarter = cv::imread(*path, cv::IMREAD_REDUCED_GRAYSCALE_4);
  if (quarter.empty()) return SendError(res, 404, *path + ": cannot read");
  cv::Mat small;
  const double scale = static_cast<double>(kThumbnailWidth) / quarter.cols;
  cv::resize(quarter, small, cv::Size(), scale, scale, cv::INTER_AREA);
  std::vector<unsigned char> jpeg;
  cv::imencode(".jpg", small, jpeg, {cv::IMWRITE_JPEG_QUALITY, 80});
  res.set_header("Cache-Control", "no-cache");  // a retake replaces the pair
  res.set_content(reinterpret_cast<const char*>(jpeg.data()), jpeg.size(), "image/jpeg");
}

void HttpApi::StationZip(const httplib::Request& req, httplib::Response& res) {
  const std::string id = req.matches[1];
  const std::optional<std::string> dir = catalog_.StationDir(id);
  if (!dir) return SendError(res, 404, "no such station");
  const fs::path cache = fs::path(parts_.config->state_dir) / "downloads";
  std::error_code ec;
  fs::create_directories(cache, ec);
  const std::string zip = (cache / (id + ".zip")).string();
  if (Status s = WriteStationArchive(*dir, zip); !s) return SendError(res, 500, s.error());
  res.set_header("Content-Disposition", "attachment; filename=\"" + id + ".zip\"");
  SendFile(res, zip, "application/zip");
}

void HttpApi::CampaignTable(bool geopackage, httplib::Response& res) {
  const Result<std::vector<std::string>> stations = FindStations({parts_.config->stations_dir});
  if (!stations) return SendError(res, 404, stations.error());
  std::vector<nlohmann::ordered_json> rows;
  std::vector<std::string> dirs;
  for (const std::string& dir : *stations) {
    Result<nlohmann::ordered_json> row = CampaignRow(dir);
    if (!row) continue;  // a station being written may not read yet
    rows.push_back(*row);
    dirs.push_back(dir);
  }
  if (!geopackage) {
    res.set_header("Content-Disposition", "attachment; filename=\"campaign.csv\"");
    return res.set_content(CampaignCsv(rows), "text/csv; charset=utf-8");
  }
  // Written aside and published atomically: two downloads at once each write their own. The
  // temporary name keeps .gpkg, which GDAL's GeoPackage driver wants.
  const fs::path folder = fs::path(parts_.config->state_dir) / "downloads";
  std::error_code ec;
  fs::create_directories(folder, ec);
  const std::string file = (folder / "campaign.gpkg").string();
  const std::string partial = TemporaryPathFor((folder / "campaign").string()) + ".gpkg";
  if (Status s = WriteCampaignGeoPackage(rows, dirs, partial); !s) {
    fs::remove(partial, ec);
    return SendError(res, 500, s.error());
  }
  if (Status s = PublishAtomically(partial, file); !s) return SendError(res, 500, s.error());
  res.set_header("Content-Disposition", "attachment; filename=\"campaign.gpkg\"");
  SendFile(res, file, "application/geopackage+sqlite3");
}

// {"before": STATION, "after": STATION}: topostation diff of the two into STATE/diffs.
void HttpApi::PostDiff(const httplib::Request& req, httplib::Response& res) {
  const nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
  std::optional<std::string> dirs[2];
  const char* keys[2] = {"before", "after"};
  for (int i = 0; i < 2; ++i) {
    if (!body.is_object() || !body.contains(keys[i]) || !body[keys[i]].is_string())
      return SendError(res, 400, std::string(keys[i]) + ": missing (a station id)");
    dirs[i] = catalog_.StationDir(body[keys[i]].get<std::string>());
    if (!dirs[i]) return SendError(res, 404, std::string(keys[i]) + ": no such station");
  }
  const std::string id =
      body["before"].get<std::string>() + "--" + body["after"].get<std::string>();
  const fs::path out = fs::path(parts_.config->state_dir) / "diffs" / id;
  try {
    const DiffProducts diff = WriteDiffProducts(*dirs[0], *dirs[1], out.string(), {});
    SendJson(res, 200, {{"id", id}, {"change", diff.json}});
  } catch (const CommandError& e) {
    SendError(res, 422, e.what());
  }
}

}  // namespace ts::daemon
