#pragma once
// Strict, typed reading of YAML mappings for configuration files. Every error names the
// dotted path of the field ("cameras.left.width_px: must be a positive integer"); loaders
// prefix the file name. Unknown keys are errors (a typo must not silently fall back to a
// default). Errors are thrown as ConfigError inside the loaders and never leave them.
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ts {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class YamlMap {
 public:
  // Throws ConfigError if node is not a mapping. path is "" for the document root.
  YamlMap(const YAML::Node& node, std::string path);

  bool Has(const std::string& key) const;
  YamlMap Map(const std::string& key);
  // Required values: finite numbers, integers in range, non-empty strings.
  double Double(const std::string& key);
  double Double(const std::string& key, double fallback);
  double PositiveDouble(const std::string& key);
  int Int(const std::string& key, int min_value, int max_value);
  int Int(const std::string& key, int min_value, int max_value, int fallback);
  bool Bool(const std::string& key, bool fallback);
  std::string String(const std::string& key);
  std::string String(const std::string& key, const std::string& fallback);
  // Fixed-length list of finite numbers.
  std::vector<double> Doubles(const std::string& key, size_t count);
  std::vector<std::string> Strings(const std::string& key);
  Eigen::Vector3d Vector3(const std::string& key, const Eigen::Vector3d& fallback);
  // A list of mappings, each with the path "key[i]".
  std::vector<YamlMap> Maps(const std::string& key);

  // Throws naming the first key that no accessor asked for.
  void RejectUnknownKeys() const;
  // Throws naming the first key not in `known`; for mappings whose keys are alternatives, so
  // that a misspelt key is reported as such and not as a missing alternative.
  void RejectKeysOtherThan(std::initializer_list<const char*> known) const;
  // "cameras.left.width_px" for key "width_px".
  std::string PathOf(const std::string& key) const;
  const std::string& path() const { return path_; }
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

 private:
  YAML::Node Get(const std::string& key);
  YAML::Node node_;
  std::string path_;
  std::set<std::string> used_;
};

// Loads a YAML file; throws ConfigError "line L, column C: ..." on a syntax error.
YAML::Node LoadYamlFile(const std::string& file);
// The same for text (a request's body).
YAML::Node LoadYamlText(const std::string& text);

}  // namespace ts
