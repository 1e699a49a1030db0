#include "station/daemon/station_catalog.h"

#include <filesystem>

#include "processing/io/json_fields.h"
#include "processing/io/station_manifest.h"
#include "station/daemon/daemon_config.h"
#include "station/station_verdict.h"

namespace ts::daemon {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> Products(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "products", ec))
    if (e.is_regular_file() && IsProductName(e.path().filename().string()))
      names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

nlohmann::json Summary(const std::string& id, const fs::path& dir) {
  const nlohmann::json manifest = ReadJsonFileOrNull((dir / kManifestFileName).string());
  const nlohmann::json report = ReadJsonFileOrNull((dir / "products/report.json").string());
  const nlohmann::json fields = ReadJsonFileOrNull((dir / "station_fields.json").string());
  nlohmann::json s = {{"id", id}, {"processed", report.is_object()}};
  if (manifest.is_object()) {
    s["created_utc"] = manifest.value("created_utc", "");
    s["pairs"] = manifest.contains("pairs") ? manifest["pairs"].size() : 0;
    s["planned_pairs"] = manifest.contains("capture_plan") ? manifest["capture_plan"].size() : 0;
  }
  if (fields.is_object())
    for (const char* key : {"line", "operator", "instrument_height_m"})
      if (fields.contains(key)) s[key] = fields[key];
  if (report.is_object())
    for (const char* key : {"terrain_correction_mgal", "terrain_correction_sigma_mgal", "verdict"})
      if (report.contains(key)) s[key] = report[key];
  s["assessment"] = JudgeStationDir(dir.string()).ToJson();
  return s;
}

}  // namespace

bool IsProductName(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
      return false;
  return true;
}

const char* ContentTypeOf(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg") return "image/jpeg";
  if (ext == ".tif") return "image/tiff";
  if (ext == ".csv") return "text/csv";
  return "application/octet-stream";
}

nlohmann::json StationCatalog::List() const {
  nlohmann::json list = nlohmann::json::array();
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, std::string>> found;
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    const std::string id = e.path().filename().string();
    if (IsStationId(id) && e.is_directory() && fs::exists(e.path() / kManifestFileName))
      found.emplace_back(fs::last_write_time(e.path() / kManifestFileName, ec), id);
  }
  std::sort(found.rbegin(), found.rend());
  for (const auto& [time, id] : found) list.push_back(Summary(id, fs::path(dir_) / id));
  return list;
}

std::optional<nlohmann::json> StationCatalog::Get(const std::string& id) const {
  if (!IsStationId(id)) return std::nullopt;
  const fs::path dir = fs::path(dir_) / id;
  if (!fs::exists(dir / kManifestFileName)) return std::nullopt;
  nlohmann::json j = Summary(id, dir);
  j["manifest"] = ReadJsonFileOrNull((dir / kManifestFileName).string());
  j["fields"] = ReadJsonFileOrNull((dir / "station_fields.json").string());
  j["report"] = ReadJsonFileOrNull((dir / "products/report.json").string());
  j["terrain_correction"] = ReadJsonFileOrNull((dir / "products/terrain_correction.json").string());
  j["products"] = Products(dir);
  return j;
}

std::optional<std::string> StationCatalog::StationDir(const std::string& id) const {
  if (!IsStationId(id)) return std::nullopt;
  const fs::path dir = fs::path(dir_) / id;
  if (!fs::exists(dir / kManifestFileName)) return std::nullopt;
  return dir.string();
}

std::optional<std::string> StationCatalog::PairImagePath(const std::string& id, int index,
                                                         Side side) const {
  const std::optional<std::string> dir = StationDir(id);
  if (!dir) return std::nullopt;
  const Result<StationManifest> m = LoadStationManifest(*dir);
  if (!m) return std::nullopt;
  for (const PairRecord& p : m->pairs)
    if (p.index == index)
      return (fs::path(*dir) / (side == Side::kLeft ? p.left.file : p.right.file)).string();
  return std::nullopt;
}

std::optional<std::string> StationCatalog::ProductPath(const std::string& id,
                                                       const std::string& name) const {
  if (!IsStationId(id) || !IsProductName(name)) return std::nullopt;
  const fs::path products = fs::path(dir_) / id / "products";
  const fs::path file = products / name;
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(file, ec))) return std::nullopt;
  const fs::path real = fs::canonical(file, ec);
  if (ec || real.parent_path() != fs::canonical(products, ec)) return std::nullopt;
  return real.string();
}

}  // namespace ts::daemon
