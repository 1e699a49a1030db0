#include "station/station_verdict.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "processing/common/angles.h"
#include "processing/geometry/capture_plan.h"
#include "processing/io/json_fields.h"
#include "processing/io/station_manifest.h"

namespace ts {
namespace {

// A sector with at least this share of its cells seen: a retake adds little.
constexpr double kSeenShare = 0.95;
// A retake worth the operator's time lowers sigma by at least a tenth.
constexpr double kWorthwhileLowering = 0.1;

double Number(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

std::string RingName(const nlohmann::json& ring) {
  const double inner = Number(ring, "inner_m"), outer = Number(ring, "outer_m");
  char text[64];
  if (std::isfinite(outer))
    std::snprintf(text, sizeof text, "%.0f-%.0f m ring", inner, outer);
  else
    std::snprintf(text, sizeof text, "ground beyond %.0f m", inner);
  return text;
}

// The poses that look toward `bearing`: the nearest pan within half a pose's spacing; the
// main row's (lowest tilt) for the near rings, every row's for the far ones, which the upper
// poses reach where the ground rises.
std::vector<StagePose> PosesToward(const std::vector<StagePose>& plan, double bearing_deg,
                                   bool far) {
  double nearest = 360.0;
  for (const StagePose& p : plan)
    nearest = std::min(nearest, AngleBetweenDeg(p.pan_deg, bearing_deg));
  std::vector<StagePose> toward;
  for (const StagePose& p : plan)
    if (AngleBetweenDeg(p.pan_deg, bearing_deg) <= nearest + 1e-6) toward.push_back(p);
  if (far || toward.empty()) return toward;
  const StagePose* lowest = &toward.front();
  for (const StagePose& p : toward)
    if (p.tilt_deg < lowest->tilt_deg) lowest = &p;
  return {*lowest};
}

std::string PosesText(const std::vector<StagePose>& poses, const std::vector<StagePose>& plan) {
  auto upper = [&](const StagePose& p) {
    for (const StagePose& q : plan)
      if (AngleBetweenDeg(q.pan_deg, p.pan_deg) < 1e-6 && q.tilt_deg < p.tilt_deg - 1e-6)
        return true;
    return false;
  };
  std::string text;
  for (size_t i = 0; i < poses.size(); ++i) {
    char one[80];
    std::snprintf(one, sizeof one, "%s %s at %.0f°", i ? " and the" : "the",
                  upper(poses[i]) ? "upper pose" : "pose", poses[i].pan_deg);
    text += one;
  }
  return text;
}

// The ring and sector that most of sigma comes from.
struct Worst {
  const nlohmann::json* ring = nullptr;
  const nlohmann::json* sector = nullptr;
};

template <class Score>
Worst WorstBy(const nlohmann::json& rings, double max_inner_m, Score score) {
  Worst w;
  double best = -INFINITY;
  for (const nlohmann::json& ring : rings) {
    if (!(Number(ring, "inner_m") < max_inner_m) || !ring.contains("sectors")) continue;
    for (const nlohmann::json& sector : ring["sectors"]) {
      const double s = score(ring, sector);
      if (s > best) best = s, w = {&ring, &sector};
    }
  }
  return w;
}

}  // namespace

nlohmann::json StationVerdict::ToJson() const {
  nlohmann::json poses = nlohmann::json::array();
  for (const StagePose& p : retake)
    poses.push_back({{"pan_deg", p.pan_deg}, {"tilt_deg", p.tilt_deg}});
  return {{"verdict", verdict}, {"text", text}, {"retake", poses}};
}

StationVerdict JudgeStation(const nlohmann::json& tc, const std::vector<StagePose>& plan,
                            double required_sigma_mgal, double nearest_view_m) {
  StationVerdict v;
  if (!tc.is_object()) return {"not processed", "not processed yet", {}};
  const nlohmann::json rings = tc.value("rings", nlohmann::json::array());
  char text[400];
  if (tc.value("verdict", "") == "unusable") {
    // The least seen direction within 30 m that a view reaches.
    const Worst w = WorstBy(rings, 30.0, [&](const nlohmann::json& ring, const nlohmann::json& s) {
      return Number(ring, "outer_m") > nearest_view_m ? -Number(s, "seen") : -INFINITY;
    });
    v.verdict = "unusable";
    v.text = "no terrain correction: " + tc.value("unusable_because", std::string("unusable"));
    if (w.sector) {
      v.retake = PosesToward(plan, Number(*w.sector, "bearing_deg"), true);
      std::snprintf(text, sizeof text, "; the least seen direction is %.0f°: retake %s",
                    Number(*w.sector, "bearing_deg"), PosesText(v.retake, plan).c_str());
      v.text += text;
    }
    return v;
  }
  const double sigma = Number(tc, "sigma_mgal");
  if (sigma <= required_sigma_mgal) {
    std::snprintf(text, sizeof text, "good: σ %.4f mGal is within the %.4f mGal you asked for",
                  sigma, required_sigma_mgal);
    return {"good", text, {}};
  }
  std::snprintf(text, sizeof text, "σ %.4f mGal exceeds the %.4f mGal you asked for", sigma,
                required_sigma_mgal);
  v.text = text;
  // What a retake can lower: ground a view reaches that the cameras did not see. The sector
  // with the most of it is named when taking it again would lower sigma by a tenth or more.
  const Worst fixable =
      WorstBy(rings, INFINITY, [&](const nlohmann::json& ring, const nlohmann::json& s) {
        const bool reached =
            Number(ring, "outer_m") > nearest_view_m || !ring["outer_m"].is_number();
        return reached && Number(s, "seen") < kSeenShare ? Number(s, "sigma_mgal") : -INFINITY;
      });
  if (fixable.sector) {
    const double part = Number(*fixable.sector, "sigma_mgal");
    const double without = std::sqrt(std::max(0.0, sigma * sigma - part * part));
    if (part > 0 && without <= (1.0 - kWorthwhileLowering) * sigma) {
      const double bearing = Number(*fixable.sector, "bearing_deg");
      v.verdict = "retake";
      v.retake = PosesToward(plan, bearing, Number(*fixable.ring, "inner_m") >= 20.0);
      std::snprintf(text, sizeof text,
                    ": the %s is %.0f %% covered, toward %.0f° only %.0f %% seen; retake %s",
                    RingName(*fixable.ring).c_str(), 100 * Number(*fixable.ring, "coverage"),
                    bearing, 100 * Number(*fixable.sector, "seen"),
                    PosesText(v.retake, plan).c_str());
      v.text += text;
      return v;
    }
  }
  // No retake would help: say where sigma comes from.
  const Worst w = WorstBy(rings, INFINITY, [](const nlohmann::json&, const nlohmann::json& s) {
    return Number(s, "sigma_mgal");
  });
  v.verdict = "as good as it gets";
  if (!w.sector) {
    v.text +=
        ": its terrain correction has no sector table (an older version processed it): "
        "process the station again to see where σ comes from";
    return v;
  }
  const double bearing = Number(*w.sector, "bearing_deg"), seen = Number(*w.sector, "seen");
  const std::string ring = RingName(*w.ring);
  if (Number(*w.ring, "outer_m") <= nearest_view_m)
    std::snprintf(text, sizeof text,
                  ": most of it is the %s toward %.0f°, nearer than any view reaches (%.1f m): "
                  "measure the ground's fall around the mark by hand",
                  ring.c_str(), bearing, nearest_view_m);
  else if (seen >= kSeenShare)
    std::snprintf(text, sizeof text,
                  ": most of it is the %s toward %.0f°, which was seen (%.0f %% of its cells): "
                  "the ground's own roughness, which a retake would not lower",
                  ring.c_str(), bearing, 100 * seen);
  else
    std::snprintf(text, sizeof text,
                  ": it is spread over many directions (the most, the %s toward %.0f°): no "
                  "single retake would lower it by a tenth",
                  ring.c_str(), bearing);
  v.text += text;
  return v;
}

StationVerdict JudgeStationDir(const std::string& dir) {
  namespace fs = std::filesystem;
  const nlohmann::json fields =
      ReadJsonFileOrNull((fs::path(dir) / "station_fields.json").string());
  const nlohmann::json tc =
      ReadJsonFileOrNull((fs::path(dir) / "products/terrain_correction.json").string());
  const Result<StationManifest> manifest = LoadStationManifest(dir);
  const std::vector<StagePose> plan = manifest ? manifest->plan : std::vector<StagePose>();
  double nearest_view_m = 0.0;
  if (manifest && !plan.empty()) {
    double lowest = plan.front().tilt_deg;
    for (const StagePose& p : plan) lowest = std::min(lowest, p.tilt_deg);
    nearest_view_m = NearestGroundRangeM(manifest->calibration, lowest);
  }
  double required = Number(fields, "required_sigma_mgal");
  if (!(required > 0)) required = kDefaultRequiredSigmaMgal;
  return JudgeStation(tc, plan, required, nearest_view_m);
}

}  // namespace ts
