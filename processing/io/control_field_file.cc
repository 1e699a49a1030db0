#include "processing/io/control_field_file.h"

#include <yaml-cpp/yaml.h>

#include <functional>
#include <set>

#include "processing/io/atomic_file.h"
#include "processing/io/yaml_map.h"

namespace ts {

int ControlField::IndexOf(int id) const {
  for (size_t i = 0; i < targets.size(); ++i)
    if (targets[i].id == id) return static_cast<int>(i);
  return -1;
}

namespace {

constexpr int kMaxId = 1000000000;

ControlField ControlFieldOf(YamlMap root) {
  YamlMap field = root.Map("control_field");
  field.Int("version", 1, 1);
  ControlField f;
  std::set<int> ids;
  for (YamlMap& t : field.Maps("targets")) {
    FieldTarget target;
    target.id = t.Int("id", 0, kMaxId);
    if (!ids.insert(target.id).second)
      t.Fail("id", std::to_string(target.id) + " twice: each target needs its own id");
    target.position_m = {t.Double("x"), t.Double("y"), t.Double("z")};
    target.sigma_m = t.Double("sigma_m");
    if (target.sigma_m < 0.0) t.Fail("sigma_m", "must not be negative");
    target.diameter_m = t.PositiveDouble("diameter_m");
    t.RejectUnknownKeys();
    f.targets.push_back(target);
  }
  if (f.targets.size() < 6) field.Fail("targets", "a control field needs at least 6 targets");
  field.RejectUnknownKeys();
  root.RejectUnknownKeys();
  return f;
}

std::vector<ImageMarks> MarksOf(YamlMap root) {
  std::vector<ImageMarks> all;
  for (YamlMap& m : root.Maps("marks")) {
    ImageMarks image{m.String("image"), {}};
    std::set<int> ids;
    for (YamlMap& t : m.Maps("targets")) {
      TargetMark mark{t.Int("id", 0, kMaxId), {t.Double("x"), t.Double("y")}};
      if (!ids.insert(mark.id).second) t.Fail("id", std::to_string(mark.id) + " twice");
      t.RejectUnknownKeys();
      image.marks.push_back(mark);
    }
    m.RejectUnknownKeys();
    all.push_back(std::move(image));
  }
  root.RejectUnknownKeys();
  return all;
}

// `read(root)` over the node `load()` gives; errors prefixed with `name` when there is one.
template <class Read>
auto ReadYaml(const std::function<YAML::Node()>& load, const std::string& name, Read read)
    -> Result<decltype(read(std::declval<YamlMap>()))> {
  try {
    return read(YamlMap(load(), ""));
  } catch (const ConfigError& e) {
    return Error{name.empty() ? std::string(e.what()) : name + ": " + e.what()};
  }
}

}  // namespace

Result<ControlField> LoadControlField(const std::string& file) {
  return ReadYaml([&] { return LoadYamlFile(file); }, file, ControlFieldOf);
}

Result<ControlField> ParseControlField(const std::string& text) {
  return ReadYaml([&] { return LoadYamlText(text); }, "", ControlFieldOf);
}

Status SaveControlField(const ControlField& field, const std::string& file) {
  YAML::Emitter out;
  out.SetDoublePrecision(15);  // survey coordinates of millions of metres, to the micrometre
  out << YAML::BeginMap << YAML::Key << "control_field" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "version" << YAML::Value << 1;
  out << YAML::Key << "targets" << YAML::Value << YAML::BeginSeq;
  for (const FieldTarget& t : field.targets)
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << t.id << YAML::Key
        << "x" << YAML::Value << t.position_m.x() << YAML::Key << "y" << YAML::Value
        << t.position_m.y() << YAML::Key << "z" << YAML::Value << t.position_m.z() << YAML::Key
        << "sigma_m" << YAML::Value << t.sigma_m << YAML::Key << "diameter_m" << YAML::Value
        << t.diameter_m << YAML::EndMap;
  out << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
  return WriteFileAtomically(file, std::string(out.c_str()) + "\n");
}

Result<std::vector<ImageMarks>> LoadTargetMarks(const std::string& file) {
  return ReadYaml([&] { return LoadYamlFile(file); }, file, MarksOf);
}

Result<std::vector<ImageMarks>> ParseTargetMarks(const std::string& text) {
  return ReadYaml([&] { return LoadYamlText(text); }, "", MarksOf);
}

Status SaveTargetMarks(const std::vector<ImageMarks>& marks, const std::string& file) {
  YAML::Emitter out;
  out.SetDoublePrecision(8);
  out << YAML::BeginMap << YAML::Key << "marks" << YAML::Value << YAML::BeginSeq;
  for (const ImageMarks& image : marks) {
    out << YAML::BeginMap << YAML::Key << "image" << YAML::Value << image.image;
    out << YAML::Key << "targets" << YAML::Value << YAML::BeginSeq;
    for (const TargetMark& m : image.marks)
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << m.id << YAML::Key
          << "x" << YAML::Value << m.pixel.x() << YAML::Key << "y" << YAML::Value << m.pixel.y()
          << YAML::EndMap;
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return WriteFileAtomically(file, std::string(out.c_str()) + "\n");
}

const ImageMarks* MarksOfImage(const std::vector<ImageMarks>& marks, const std::string& path) {
  for (const ImageMarks& m : marks) {
    if (m.image.empty() || path.size() < m.image.size()) continue;
    const size_t start = path.size() - m.image.size();
    if (path.compare(start, m.image.size(), m.image) == 0 && (start == 0 || path[start - 1] == '/'))
      return &m;
  }
  return nullptr;
}

}  // namespace ts
