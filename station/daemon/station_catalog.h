#pragma once
// The stations the daemon keeps, as the API shows them: a summary per station, one station's
// manifest, fields, report and terrain correction, and the path of one of its products. Ids
// and product names are checked before any path is built from them.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/result.h"

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

 private:
  const std::string dir_;
};

// [A-Za-z0-9_-][A-Za-z0-9_.-]{0,63}: a product file name, never a path.
bool IsProductName(const std::string& name);
const char* ContentTypeOf(const std::string& name);

}  // namespace ts::daemon
