#pragma once
// The stations the daemon keeps, as the API shows them: a summary per station (with the
// operator's verdict, station_verdict.h), one station's manifest, fields, report and terrain
// correction, the path of one of its products or of a pair's image. Ids
// and product names are checked before any path is built from them.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/result.h"
#include "processing/geometry/calibration.h"

namespace ts::daemon {

class StationCatalog {
 public:
  explicit StationCatalog(std::string stations_dir) : dir_(std::move(stations_dir)) {}
  nlohmann::json List() const;  // newest first
  // nullopt when there is no such station.
  std::optional<nlohmann::json> Get(const std::string& id) const;
  // The product's file when `name` is a plain file name in the station's products/ (no link
  // leading elsewhere); nullopt otherwise.
  std::optional<std::string> ProductPath(const std::string& id, const std::string& name) const;
  // The image of pair `index` on `side` as the manifest records it; nullopt when there is none.
  std::optional<std::string> PairImagePath(const std::string& id, int index, Side side) const;
  // The station's directory; nullopt when there is no such station.
  std::optional<std::string> StationDir(const std::string& id) const;

 private:
  const std::string dir_;
};

// [A-Za-z0-9_-][A-Za-z0-9_.-]{0,63}: a product file name, never a path.
bool IsProductName(const std::string& name);
const char* ContentTypeOf(const std::string& name);

}  // namespace ts::daemon
