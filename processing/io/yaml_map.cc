#include "processing/io/yaml_map.h"

#include <cmath>
#include <filesystem>
#include <limits>

namespace ts {

YamlMap::YamlMap(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
  if (!node_.IsMap())
    throw ConfigError((path_.empty() ? std::string("document") : path_) + ": must be a mapping");
}

std::string YamlMap::PathOf(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void YamlMap::Fail(const std::string& key, const std::string& message) const {
  throw ConfigError(PathOf(key) + ": " + message);
}

bool YamlMap::Has(const std::string& key) const { return bool(node_[key]); }

YAML::Node YamlMap::Get(const std::string& key) {
  used_.insert(key);
  const YAML::Node value = node_[key];
  if (!value || value.IsNull()) Fail(key, "missing");
  return value;
}

YamlMap YamlMap::Map(const std::string& key) { return YamlMap(Get(key), PathOf(key)); }

std::vector<YamlMap> YamlMap::Maps(const std::string& key) {
  const YAML::Node list = Get(key);
  if (!list.IsSequence()) Fail(key, "must be a list");
  std::vector<YamlMap> maps;
  for (size_t i = 0; i < list.size(); ++i)
    maps.emplace_back(list[i], PathOf(key) + "[" + std::to_string(i) + "]");
  return maps;
}

double YamlMap::Double(const std::string& key) {
  const YAML::Node v = Get(key);
  double d = 0.0;
  if (!v.IsScalar() || !YAML::convert<double>::decode(v, d)) Fail(key, "must be a number");
  if (!std::isfinite(d)) Fail(key, "must be finite, got " + v.Scalar());
  return d;
}

double YamlMap::Double(const std::string& key, double fallback) {
  return Has(key) ? Double(key) : (used_.insert(key), fallback);
}

double YamlMap::PositiveDouble(const std::string& key) {
  const double d = Double(key);
  if (!(d > 0.0)) Fail(key, "must be positive");
  return d;
}

int YamlMap::Int(const std::string& key, int min_value, int max_value) {
  const YAML::Node v = Get(key);
  long long i = 0;
  if (!v.IsScalar() || !YAML::convert<long long>::decode(v, i)) Fail(key, "must be an integer");
  if (i < min_value || i > max_value)
    Fail(key, "must be in [" + std::to_string(min_value) + ", " + std::to_string(max_value) +
                  "], got " + v.Scalar());
  return static_cast<int>(i);
}

int YamlMap::Int(const std::string& key, int min_value, int max_value, int fallback) {
  return Has(key) ? Int(key, min_value, max_value) : (used_.insert(key), fallback);
}

bool YamlMap::Bool(const std::string& key, bool fallback) {
  if (!Has(key)) return used_.insert(key), fallback;
  const YAML::Node v = Get(key);
  bool b = false;
  if (!v.IsScalar() || !YAML::convert<bool>::decode(v, b)) Fail(key, "must be true or false");
  return b;
}

std::string YamlMap::String(const std::string& key) {
  const YAML::Node v = Get(key);
  if (!v.IsScalar() || v.Scalar().empty()) Fail(key, "must be a non-empty string");
  return v.Scalar();
}

std::string YamlMap::String(const std::string& key, const std::string& fallback) {
  return Has(key) ? String(key) : (used_.insert(key), fallback);
}

std::vector<double> YamlMap::Doubles(const std::string& key, size_t count) {
  const YAML::Node v = Get(key);
  if (!v.IsSequence() || v.size() != count)
    Fail(key, "must be a list of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (size_t i = 0; i < count; ++i) {
    double d = 0.0;
    if (!v[i].IsScalar() || !YAML::convert<double>::decode(v[i], d) || !std::isfinite(d))
      Fail(key, "element " + std::to_string(i) + " must be a finite number");
    out.push_back(d);
  }
  return out;
}

std::vector<std::string> YamlMap::Strings(const std::string& key) {
  const YAML::Node v = Get(key);
  if (!v.IsSequence()) Fail(key, "must be a list of strings");
  std::vector<std::string> out;
  for (size_t i = 0; i < v.size(); ++i) {
    if (!v[i].IsScalar() || v[i].Scalar().empty())
      Fail(key, "element " + std::to_string(i) + " must be a non-empty string");
    out.push_back(v[i].Scalar());
  }
  return out;
}

Eigen::Vector3d YamlMap::Vector3(const std::string& key, const Eigen::Vector3d& fallback) {
  if (!Has(key)) return used_.insert(key), fallback;
  const std::vector<double> v = Doubles(key, 3);
  return {v[0], v[1], v[2]};
}

void YamlMap::RejectUnknownKeys() const {
  for (const auto& entry : node_) {
    const std::string key = entry.first.as<std::string>("");
    if (!used_.count(key)) Fail(key, "unknown key");
  }
}

void YamlMap::RejectKeysOtherThan(std::initializer_list<const char*> known) const {
  for (const auto& entry : node_) {
    const std::string key = entry.first.as<std::string>("");
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found) Fail(key, "unknown key");
  }
}

namespace {

ConfigError SyntaxError(const YAML::ParserException& e) {
  return ConfigError("line " + std::to_string(e.mark.line + 1) + ", column " +
                     std::to_string(e.mark.column + 1) + ": " + e.msg);
}

}  // namespace

YAML::Node LoadYamlFile(const std::string& file) {
  if (!std::filesystem::is_regular_file(file)) throw ConfigError("cannot read file");
  try {
    YAML::Node root = YAML::LoadFile(file);
    if (!root || root.IsNull()) throw ConfigError("file is empty");
    return root;
  } catch (const YAML::ParserException& e) {
    throw SyntaxError(e);
  } catch (const YAML::BadFile&) {
    throw ConfigError("cannot read file");
  }
}

YAML::Node LoadYamlText(const std::string& text) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw SyntaxError(e);
  }
}

}  // namespace ts
