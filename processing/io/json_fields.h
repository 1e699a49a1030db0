#pragma once
// Typed reading of JSON objects whose errors name the field path ("pairs[3].left.sha256:
// missing"), the JSON twin of yaml_map.h. Throws ConfigError; loaders add the file name.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "processing/io/yaml_map.h"

namespace ts {

class JsonObject {
 public:
  // Borrows value (it must outlive this); throws ConfigError if it is not an object.
  JsonObject(const nlohmann::json& value, std::string path);

  bool Has(const std::string& key) const;       // present and not null
  double Number(const std::string& key) const;  // finite
  int Int(const std::string& key, int min_value, int max_value) const;
  int64_t Int64(const std::string& key) const;
  std::string String(const std::string& key) const;  // non-empty
  JsonObject Object(const std::string& key) const;
  std::vector<JsonObject> Array(const std::string& key) const;  // array of objects
  std::string Dump() const { return value_->dump(); }
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

 private:
  const nlohmann::json& Get(const std::string& key) const;
  std::string PathOf(const std::string& key) const;
  const nlohmann::json* value_;
  std::string path_;
};

// A JSON file's content; null when the file is missing or not JSON (for optional files such as
// a station's products, read by callers that check each field's type).
nlohmann::json ReadJsonFileOrNull(const std::string& file);

// Converts a YAML document to JSON; scalars become integers, numbers or booleans when they
// read as such, otherwise strings.
nlohmann::json JsonFromYaml(const YAML::Node& node);

}  // namespace ts
