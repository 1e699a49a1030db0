#include "station/daemon/job_request.h"

#include <cmath>
#include <set>

#include "station/daemon/daemon_config.h"

namespace ts::daemon {
namespace {

constexpr size_t kMaxTextChars = 2000;
constexpr size_t kMaxGcps = 100;

Status CheckText(const nlohmann::json& body, const char* key) {
  if (!body.contains(key)) return {};
  const nlohmann::json& v = body[key];
  if (!v.is_string() || v.get_ref<const std::string&>().size() > kMaxTextChars)
    return Error{std::string(key) + ": must be text of at most 2000 characters"};
  return {};
}

Status CheckBoolean(const nlohmann::json& body, const char* key) {
  if (body.contains(key) && !body[key].is_boolean())
    return Error{std::string(key) + ": must be true or false"};
  return {};
}

Status CheckNumber(const nlohmann::json& object, const std::string& path, const char* key,
                   double lo, double hi, bool required) {
  if (!object.contains(key)) {
    if (required) return Error{path + key + ": missing"};
    return {};
  }
  const nlohmann::json& v = object[key];
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo ||
      v.get<double>() > hi)
    return Error{path + key + ": must be a number within " + std::to_string(lo) + " and " +
                 std::to_string(hi)};
  return {};
}

Status CheckKeys(const nlohmann::json& object, const std::string& path,
                 const std::set<std::string>& known) {
  for (const auto& [key, value] : object.items())
    if (!known.count(key)) return Error{path + key + ": unknown field"};
  return {};
}

Status CheckGnss(const nlohmann::json& g) {
  if (!g.is_object()) return Error{"gnss: must be an object"};
  if (Status s = CheckKeys(g, "gnss.", {"lat_deg", "lon_deg", "height_m", "sigma_m"}); !s) return s;
  for (Status s : {CheckNumber(g, "gnss.", "lat_deg", -90, 90, true),
                   CheckNumber(g, "gnss.", "lon_deg", -180, 180, true),
                   CheckNumber(g, "gnss.", "height_m", -11000, 9000, false),
                   CheckNumber(g, "gnss.", "sigma_m", 0, 1000, false)})
    if (!s) return s;
  return {};
}

Status CheckGcps(const nlohmann::json& list) {
  if (!list.is_array() || list.size() > kMaxGcps)
    return Error{"gcps: must be a list of at most 100 points"};
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = "gcps[" + std::to_string(i) + "].";
    const nlohmann::json& p = list[i];
    if (!p.is_object()) return Error{path + ": must be an object"};
    if (Status s = CheckKeys(p, path, {"id", "x", "y", "z", "sigma_m"}); !s) return s;
    if (!p.contains("id") || !p["id"].is_string() || !IsStationId(p["id"].get<std::string>()))
      return Error{path + "id: must be [A-Za-z0-9_-]{1,64}"};
    for (const char* axis : {"x", "y", "z"})
      if (Status s = CheckNumber(p, path, axis, -1e8, 1e8, true); !s) return s;
    if (Status s = CheckNumber(p, path, "sigma_m", 0, 100, false); !s) return s;
  }
  return {};
}

// The request as the job keeps it: its fields less the kind.
JobRequest RequestOf(JobKind kind, const std::string& station, const nlohmann::json& body) {
  JobRequest r;
  r.kind = kind;
  r.station = station;
  r.fields = body;
  r.fields.erase("kind");
  return r;
}

constexpr size_t kMaxCalibrationStations = 20;

Result<JobRequest> ParseCalibrateRig(const nlohmann::json& body) {
  if (Status s = CheckKeys(body, "", {"kind", "stations", "refine_cameras", "notes"}); !s)
    return Error{s.error()};
  if (Status s = CheckText(body, "notes"); !s) return Error{s.error()};
  if (Status s = CheckBoolean(body, "refine_cameras"); !s) return Error{s.error()};
  const nlohmann::json& list = body.value("stations", nlohmann::json());
  if (!list.is_array() || list.empty() || list.size() > kMaxCalibrationStations)
    return Error{"stations: must be a list of 1-20 station ids"};
  std::vector<std::string> stations;
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_string() || !IsStationId(list[i].get<std::string>()))
      return Error{"stations[" + std::to_string(i) + "]: must be 1-64 letters, digits, '_' or '-'"};
    stations.push_back(list[i].get<std::string>());
  }
  JobRequest r = RequestOf(JobKind::kCalibrateRig, stations.front(), body);
  r.stations = std::move(stations);
  return r;
}

Status CheckStation(const nlohmann::json& body) {
  if (!body.contains("station") || !body["station"].is_string() ||
      !IsStationId(body["station"].get<std::string>()))
    return Error{"station: must be 1-64 letters, digits, '_' or '-'"};
  return {};
}

// The poses a verdict named (station_verdict.h): 1-20 of them, within the stage's reach.
Result<JobRequest> ParseRetake(const nlohmann::json& body) {
  if (Status s = CheckKeys(body, "", {"kind", "station", "poses", "notes"}); !s)
    return Error{s.error()};
  if (Status s = CheckStation(body); !s) return Error{s.error()};
  if (Status s = CheckText(body, "notes"); !s) return Error{s.error()};
  const nlohmann::json& poses = body.value("poses", nlohmann::json());
  if (!poses.is_array() || poses.empty() || poses.size() > 20)
    return Error{"poses: must be a list of 1-20 {\"pan_deg\", \"tilt_deg\"}"};
  for (size_t i = 0; i < poses.size(); ++i) {
    const std::string path = "poses[" + std::to_string(i) + "].";
    if (!poses[i].is_object()) return Error{path + ": must be an object"};
    if (Status s = CheckKeys(poses[i], path, {"pan_deg", "tilt_deg"}); !s) return Error{s.error()};
    for (Status s : {CheckNumber(poses[i], path, "pan_deg", -360, 360, true),
                     CheckNumber(poses[i], path, "tilt_deg", -32, 32, true)})
      if (!s) return Error{s.error()};
  }
  return RequestOf(JobKind::kRetake, body["station"].get<std::string>(), body);
}

Result<JobRequest> ParseCaptureField(const nlohmann::json& body) {
  if (Status s = CheckKeys(body, "",
                           {"kind", "station", "field_pan_deg", "field_tilt_deg", "field_pans",
                            "field_tilts", "notes"});
      !s)
    return Error{s.error()};
  for (Status s :
       {CheckText(body, "notes"), CheckNumber(body, "", "field_pan_deg", -360, 360, false),
        CheckNumber(body, "", "field_tilt_deg", -32, 32, false),
        CheckNumber(body, "", "field_pans", 1, 36, false),
        CheckNumber(body, "", "field_tilts", 1, 9, false)})
    if (!s) return Error{s.error()};
  if (Status s = CheckStation(body); !s) return Error{s.error()};
  return RequestOf(JobKind::kCaptureField, body["station"].get<std::string>(), body);
}

// A control field session's calibration: the session a capture_field job took, the field's
// surveyed targets and the hand marks, each read as its file would be (the same checks, the
// same names of fields).
Result<JobRequest> ParseCalibrateField(const nlohmann::json& body) {
  if (Status s = CheckKeys(body, "", {"kind", "session", "control_field", "marks", "notes"}); !s)
    return Error{s.error()};
  if (Status s = CheckText(body, "notes"); !s) return Error{s.error()};
  if (!body.contains("session") || !body["session"].is_string() ||
      !IsStationId(body["session"].get<std::string>()))
    return Error{"session: must be the id of a capture_field job's session"};
  if (!body.contains("control_field")) return Error{"control_field: missing"};
  if (!body.contains("marks")) return Error{"marks: missing"};
  const Result<ControlField> field = ControlFieldOf(body);
  if (!field) return Error{field.error()};
  const Result<std::vector<ImageMarks>> marks = TargetMarksOf(body);
  if (!marks) return Error{marks.error()};
  for (size_t i = 0; i < marks->size(); ++i)
    for (size_t k = 0; k < (*marks)[i].marks.size(); ++k)
      if (field->IndexOf((*marks)[i].marks[k].id) < 0)
        return Error{"marks[" + std::to_string(i) + "].targets[" + std::to_string(k) + "].id: " +
                     std::to_string((*marks)[i].marks[k].id) + " is not a target of control_field"};
  return RequestOf(JobKind::kCalibrateField, body["session"].get<std::string>(), body);
}

}  // namespace

Result<ControlField> ControlFieldOf(const nlohmann::json& fields) {
  return ParseControlField(
      nlohmann::json{{"control_field", fields.value("control_field", nlohmann::json())}}.dump());
}

Result<std::vector<ImageMarks>> TargetMarksOf(const nlohmann::json& fields) {
  return ParseTargetMarks(
      nlohmann::json{{"marks", fields.value("marks", nlohmann::json())}}.dump());
}

Result<JobRequest> ParseJobRequest(const nlohmann::json& body) {
  if (!body.is_object()) return Error{"the body must be a JSON object"};
  if (body.value("kind", nlohmann::json()) == "calibrate_rig") return ParseCalibrateRig(body);
  if (body.value("kind", nlohmann::json()) == "capture_field") return ParseCaptureField(body);
  if (body.value("kind", nlohmann::json()) == "retake") return ParseRetake(body);
  if (body.value("kind", nlohmann::json()) == "calibrate_field") return ParseCalibrateField(body);
  if (Status s = CheckKeys(body, "",
                           {"kind", "station", "line", "instrument_height_m", "operator", "notes",
                            "gnss", "gcps", "single_row", "required_sigma_mgal"});
      !s)
    return Error{s.error()};
  if (!body.contains("kind") || !body["kind"].is_string() ||
      !JobKindFromName(body["kind"].get<std::string>()))
    return Error{
        "kind: must be survey, capture, process, retake, calibrate_rig, capture_field or "
        "calibrate_field"};
  const JobKind kind = *JobKindFromName(body["kind"].get<std::string>());
  if (Status s = CheckStation(body); !s) return Error{s.error()};
  if (Status s = CheckNumber(body, "", "required_sigma_mgal", 0.0001, 10, false); !s)
    return Error{s.error()};
  JobRequest r = RequestOf(kind, body["station"].get<std::string>(), body);
  for (const char* key : {"line", "operator", "notes"})
    if (Status s = CheckText(body, key); !s) return Error{s.error()};
  if (UsesRig(r.kind)) {
    if (Status s = CheckNumber(body, "", "instrument_height_m", 0.05, 10, true); !s)
      return Error{s.error()};
    r.instrument_height_m = body["instrument_height_m"].get<double>();
  } else if (body.contains("instrument_height_m")) {
    return Error{"instrument_height_m: a process job takes the station's own"};
  }
  if (body.contains("gnss"))
    if (Status s = CheckGnss(body["gnss"]); !s) return Error{s.error()};
  if (body.contains("gcps"))
    if (Status s = CheckGcps(body["gcps"]); !s) return Error{s.error()};
  if (Status s = CheckBoolean(body, "single_row"); !s) return Error{s.error()};
  r.single_row = body.value("single_row", r.single_row);
  return r;
}

}  // namespace ts::daemon
