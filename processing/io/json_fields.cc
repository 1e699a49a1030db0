#include "processing/io/json_fields.h"

#include <cmath>
#include <fstream>

namespace ts {

using nlohmann::json;

JsonObject::JsonObject(const json& value, std::string path)
    : value_(&value), path_(std::move(path)) {
  if (!value.is_object())
    throw ConfigError((path_.empty() ? std::string("document") : path_) + ": must be an object");
}

std::string JsonObject::PathOf(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void JsonObject::Fail(const std::string& key, const std::string& message) const {
  throw ConfigError(PathOf(key) + ": " + message);
}

const json& JsonObject::Get(const std::string& key) const {
  const auto it = value_->find(key);
  if (it == value_->end() || it->is_null()) Fail(key, "missing");
  return *it;
}

bool JsonObject::Has(const std::string& key) const {
  const auto it = value_->find(key);
  return it != value_->end() && !it->is_null();
}

double JsonObject::Number(const std::string& key) const {
  const json& v = Get(key);
  if (!v.is_number()) Fail(key, "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) Fail(key, "must be finite");
  return d;
}

int JsonObject::Int(const std::string& key, int min_value, int max_value) const {
  const json& v = Get(key);
  if (!v.is_number_integer()) Fail(key, "must be an integer");
  const int64_t i = v.get<int64_t>();
  if (i < min_value || i > max_value)
    Fail(key, "must be in [" + std::to_string(min_value) + ", " + std::to_string(max_value) + "]");
  return static_cast<int>(i);
}

int64_t JsonObject::Int64(const std::string& key) const {
  const json& v = Get(key);
  if (!v.is_number_integer()) Fail(key, "must be an integer");
  return v.get<int64_t>();
}

std::string JsonObject::String(const std::string& key) const {
  const json& v = Get(key);
  if (!v.is_string() || v.get<std::string>().empty()) Fail(key, "must be a non-empty string");
  return v.get<std::string>();
}

JsonObject JsonObject::Object(const std::string& key) const {
  return JsonObject(Get(key), PathOf(key));
}

std::vector<JsonObject> JsonObject::Array(const std::string& key) const {
  const json& v = Get(key);
  if (!v.is_array()) Fail(key, "must be an array");
  std::vector<JsonObject> out;
  for (size_t i = 0; i < v.size(); ++i)
    out.emplace_back(v[i], PathOf(key) + "[" + std::to_string(i) + "]");
  return out;
}

json JsonFromYaml(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      json out = json::object();
      for (const auto& entry : node)
        out[entry.first.as<std::string>()] = JsonFromYaml(entry.second);
      return out;
    }
    case YAML::NodeType::Sequence: {
      json out = json::array();
      for (const auto& element : node) out.push_back(JsonFromYaml(element));
      return out;
    }
    case YAML::NodeType::Scalar: {
      long long i = 0;
      double d = 0.0;
      bool b = false;
      if (YAML::convert<long long>::decode(node, i)) return i;
      if (YAML::convert<double>::decode(node, d)) return d;
      if (YAML::convert<bool>::decode(node, b)) return b;
      return node.Scalar();
    }
    default:
      return nullptr;
  }
}

nlohmann::json ReadJsonFileOrNull(const std::string& file) {
  std::ifstream in(file);
  if (!in) return nullptr;
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return nullptr;
  return j;
}

}  // namespace ts
