#include "processing/io/station_manifest.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "processing/io/atomic_file.h"
#include "processing/io/calibration_yaml.h"
#include "processing/io/json_fields.h"

namespace ts {

using nlohmann::json;

const PairRecord* StationManifest::FindPair(int index) const {
  for (const PairRecord& p : pairs)
    if (p.index == index) return &p;
  return nullptr;
}

bool StationManifest::Complete() const {
  for (size_t i = 0; i < plan.size(); ++i)
    if (!FindPair(static_cast<int>(i))) return false;
  return true;
}

std::string StationManifest::ImageFileName(int index, Side side) {
  char name[64];
  std::snprintf(name, sizeof(name), "raw/pair_%02d_%s.png", index, SideName(side));
  return name;
}

std::string UtcNowIso8601() {
  const auto now =
      std::chrono::time_point_cast<std::chrono::milliseconds>(std::chrono::system_clock::now());
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[40];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%S", &tm);
  const auto ms = now.time_since_epoch().count() % 1000;
  char out[48];
  std::snprintf(out, sizeof(out), "%s.%03dZ", buf, static_cast<int>(ms));
  return out;
}

namespace {

json PoseToJson(const StagePose& p) { return {{"pan_deg", p.pan_deg}, {"tilt_deg", p.tilt_deg}}; }

// A stage's angles: a pan within a turn either way, a tilt within a half turn (a read-back of
// 1e300 was taken as an angle).
StagePose PoseFromJson(const JsonObject& o) {
  const StagePose pose{o.Number("pan_deg"), o.Number("tilt_deg")};
  if (!(std::abs(pose.pan_deg) <= 360.0)) o.Fail("pan_deg", "must be within 360 deg");
  if (!(std::abs(pose.tilt_deg) <= 90.0)) o.Fail("tilt_deg", "must be within 90 deg");
  return pose;
}

// The timeline's fields, once for writing and reading.
template <class Timeline, class V>
void VisitTimeline(Timeline& t, V&& v) {
  v("move_s", t.move_s);
  v("settle_s", t.settle_s);
  v("stage_wait_s", t.stage_wait_s);
  v("trigger_to_frame_s", t.trigger_to_frame_s);
  v("verify_s", t.verify_s);
  v("write_s", t.write_s);
  v("pair_s", t.pair_s);
}

json TimelineToJson(const PairTimeline& t) {
  json j = json::object();
  VisitTimeline(t, [&](const char* name, double value) {
    if (std::isfinite(value)) j[name] = value;
  });
  if (t.triggers > 0) j["triggers"] = t.triggers;
  return j;
}

PairTimeline TimelineFromJson(const JsonObject& o) {
  PairTimeline t;
  VisitTimeline(t, [&](const char* name, double& value) {
    if (!o.Has(name)) return;
    value = o.Number(name);
    if (value < 0.0) o.Fail(name, "must not be negative");
  });
  if (o.Has("triggers")) t.triggers = o.Int("triggers", 0, 1000000);
  return t;
}

json PairToJson(const PairRecord& p) {
  json j = {{"index", p.index},
            {"commanded", PoseToJson(p.commanded)},
            {"readback", PoseToJson(p.readback)},
            {"exposure_us", p.exposure_us},
            {"gain_db", p.gain_db},
            {"captured_utc", p.captured_utc},
            {"left_timestamp_ns", p.left_timestamp_ns},
            {"right_timestamp_ns", p.right_timestamp_ns},
            {"left", {{"file", p.left.file}, {"sha256", p.left.sha256}}},
            {"right", {{"file", p.right.file}, {"sha256", p.right.sha256}}}};
  if (json t = TimelineToJson(p.timeline); !t.empty()) j["timeline"] = t;
  if (p.inclinometer_deg)
    j["inclinometer_deg"] = {{"x", p.inclinometer_deg->x()}, {"y", p.inclinometer_deg->y()}};
  return j;
}

ImageRecord ImageFromJson(const JsonObject& o) {
  ImageRecord r{o.String("file"), o.String("sha256")};
  const std::filesystem::path file(r.file);
  if (file.is_absolute() || r.file.find("..") != std::string::npos || !r.file.starts_with("raw/"))
    o.Fail("file", "must be a relative path inside raw/");
  if (r.sha256.size() != 64 || r.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
    o.Fail("sha256", "must be 64 lower-case hex digits");
  return r;
}

PairRecord PairFromJson(const JsonObject& o) {
  PairRecord p;
  p.index = o.Int("index", 0, 9999);
  p.commanded = PoseFromJson(o.Object("commanded"));
  p.readback = PoseFromJson(o.Object("readback"));
  p.exposure_us = o.Number("exposure_us");
  if (!(p.exposure_us > 0.0)) o.Fail("exposure_us", "must be positive");
  p.gain_db = o.Number("gain_db");
  p.captured_utc = o.String("captured_utc");
  p.left_timestamp_ns = o.Int64("left_timestamp_ns");
  p.right_timestamp_ns = o.Int64("right_timestamp_ns");
  p.left = ImageFromJson(o.Object("left"));
  p.right = ImageFromJson(o.Object("right"));
  if (o.Has("timeline")) p.timeline = TimelineFromJson(o.Object("timeline"));
  if (o.Has("inclinometer_deg")) {
    const JsonObject tilt = o.Object("inclinometer_deg");
    p.inclinometer_deg = Eigen::Vector2d(tilt.Number("x"), tilt.Number("y"));
    if (p.inclinometer_deg->cwiseAbs().maxCoeff() > 90.0)
      tilt.Fail("x", "an inclinometer reading must be within 90 deg");
  }
  return p;
}

void CheckPairs(const StationManifest& m, const JsonObject& root) {
  std::set<int> seen;
  for (size_t i = 0; i < m.pairs.size(); ++i) {
    const std::string field = "pairs[" + std::to_string(i) + "].index";
    const int index = m.pairs[i].index;
    if (index >= static_cast<int>(m.plan.size()))
      root.Fail(field, "pair " + std::to_string(index) + " is not in the capture plan (" +
                           std::to_string(m.plan.size()) + " poses)");
    if (!seen.insert(index).second)
      root.Fail(field, "pair " + std::to_string(index) + " recorded twice");
  }
}

}  // namespace

std::string ManifestToJson(const StationManifest& m) {
  json plan = json::array();
  for (const StagePose& p : m.plan) plan.push_back(PoseToJson(p));
  json pairs = json::array();
  for (const PairRecord& p : m.pairs) pairs.push_back(PairToJson(p));
  const json doc = {{"schema", kStationSchemaName},
                    {"schema_version", m.schema_version},
                    {"station_id", m.station_id},
                    {"created_utc", m.created_utc},
                    {"updated_utc", m.updated_utc},
                    {"software_version", m.software_version},
                    {"rig_name", m.rig_name},
                    {"calibration", JsonFromYaml(YAML::Load(CalibrationToYaml(m.calibration)))},
                    {"image",
                     {{"width_px", m.image_width_px},
                      {"height_px", m.image_height_px},
                      {"pixel_format", PixelFormatName(m.pixel_format)}}},
                    {"capture_plan", plan},
                    {"pairs", pairs}};
  return doc.dump(2) + "\n";
}

Result<StationManifest> ManifestFromJson(const std::string& text, const std::string& source) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    return Error{source + ": malformed or truncated JSON at byte " + std::to_string(e.byte)};
  } catch (const json::exception& e) {  // a number beyond a double, found by the fuzzer
    return Error{source + ": not a valid manifest: " + e.what()};
  }
  try {
    const JsonObject root(doc, "");
    if (root.String("schema") != kStationSchemaName)
      root.Fail("schema", std::string("must be \"") + kStationSchemaName + "\"");
    StationManifest m;
    m.schema_version = root.Int("schema_version", 0, 1000000);
    if (m.schema_version != kStationSchemaVersion)
      root.Fail("schema_version", "unsupported version " + std::to_string(m.schema_version) +
                                      " (this build reads " +
                                      std::to_string(kStationSchemaVersion) + ")");
    m.station_id = root.String("station_id");
    m.created_utc = root.String("created_utc");
    m.updated_utc = root.String("updated_utc");
    m.software_version = root.String("software_version");
    m.rig_name = root.String("rig_name");
    try {
      m.calibration =
          ParseCalibration(YamlMap(YAML::Load(root.Object("calibration").Dump()), "calibration"));
    } catch (const YAML::Exception& e) {
      root.Fail("calibration", e.what());
    }
    const JsonObject image = root.Object("image");
    m.image_width_px = image.Int("width_px", 1, 100000);
    m.image_height_px = image.Int("height_px", 1, 100000);
    const Result<PixelFormat> format = PixelFormatFromName(image.String("pixel_format"));
    if (!format) image.Fail("pixel_format", format.error());
    m.pixel_format = *format;
    // A panorama is a dozen or two pairs; thousands are a corrupt or hostile manifest, which
    // process would work through for minutes before saying anything.
    const std::vector<JsonObject> plan = root.Array("capture_plan");
    if (plan.size() > kMaxPlanPoses)
      root.Fail("capture_plan", std::to_string(plan.size()) + " poses, more than the " +
                                    std::to_string(kMaxPlanPoses) + " a station may have");
    for (const JsonObject& pose : plan) m.plan.push_back(PoseFromJson(pose));
    for (const JsonObject& pair : root.Array("pairs")) m.pairs.push_back(PairFromJson(pair));
    CheckPairs(m, root);
    return m;
  } catch (const ConfigError& e) {
    return Error{source + ": " + e.what()};
  }
}

Result<StationManifest> LoadStationManifest(const std::string& station_dir) {
  const std::string path = (std::filesystem::path(station_dir) / kManifestFileName).string();
  if (!std::filesystem::exists(path)) return Error{path + ": missing manifest"};
  Result<std::string> text = ReadWholeFile(path);
  if (!text) return Error{text.error()};
  return ManifestFromJson(*text, path);
}

Status SaveStationManifest(StationManifest* manifest, const std::string& station_dir) {
  manifest->updated_utc = UtcNowIso8601();
  if (manifest->created_utc.empty()) manifest->created_utc = manifest->updated_utc;
  const std::string path = (std::filesystem::path(station_dir) / kManifestFileName).string();
  return WriteFileAtomically(path, ManifestToJson(*manifest));
}

json CaptureTimelineJson(const std::vector<PairRecord>& pairs) {
  json list = json::array();
  std::map<std::string, std::vector<double>> values;
  for (const PairRecord& p : pairs) {
    json t = TimelineToJson(p.timeline);
    if (t.empty()) continue;
    VisitTimeline(p.timeline, [&](const char* name, double value) {
      if (std::isfinite(value)) values[name].push_back(value);
    });
    t["pair"] = p.index;
    list.push_back(t);
  }
  if (list.empty()) return nullptr;
  json total = json::object(), median = json::object();
  for (auto& [name, v] : values) {
    double sum = 0.0;
    for (double x : v) sum += x;
    total[name] = sum;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    median[name] = v[v.size() / 2];
  }
  return {{"pairs", list}, {"total_s", total}, {"median_s", median}};
}

}  // namespace ts
