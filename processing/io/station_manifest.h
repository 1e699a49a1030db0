#pragma once
// station.json, the manifest and commit record of a station directory (DESIGN.md "Station
// directory"). A pair exists when, and only when, its record is in the manifest: images are
// written first (atomically), then the manifest is rewritten atomically with the new record.
//
//   STATION/station.json
//   STATION/raw/pair_NN_{left,right}.png
//   STATION/products/...
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "processing/geometry/calibration.h"
#include "processing/geometry/capture_plan.h"
#include "processing/io/image_file.h"

namespace ts {

inline constexpr int kStationSchemaVersion = 1;
inline constexpr const char* kStationSchemaName = "topostation.station";
inline constexpr const char* kManifestFileName = "station.json";
// A panorama is 12-24 pairs (a few rows of tilt at most): more poses than this are refused.
inline constexpr size_t kMaxPlanPoses = 200;

struct ImageRecord {
  std::string file;    // relative to the station directory, e.g. "raw/pair_03_left.png"
  std::string sha256;  // lower-case hex of the file's bytes
};

// Where the capture's time went for one pair (seconds; NaN where not measured, e.g. for a
// rendered station). The stage moves to a pose while the previous pair is written, so
// move + settle overlap the previous write; stage_wait is the part that did not.
struct PairTimeline {
  double move_s = NAN;              // start command until both axes within tolerance
  double settle_s = NAN;            // then until both report IN_POSITION
  double stage_wait_s = NAN;        // the capture waited this long for the stage
  double trigger_to_frame_s = NAN;  // trigger until both frames are in (all triggers)
  int triggers = 0;                 // re-triggers and exposure retakes included
  double verify_s = NAN;            // exposure check and the look above the view
  double write_s = NAN;             // both images written and synced
  double pair_s = NAN;              // previous commit (or the capture's start) to this commit
};

struct PairRecord {
  int index = 0;             // position in the capture plan, 0-based
  StagePose commanded;       // what the stage was told
  StagePose readback;        // what its encoders reported when the images were taken
  double exposure_us = 0.0;  // both cameras (exposure is locked together)
  double gain_db = 0.0;
  std::string captured_utc;       // ISO 8601
  int64_t left_timestamp_ns = 0;  // camera timestamps
  int64_t right_timestamp_ns = 0;
  ImageRecord left;
  ImageRecord right;
  PairTimeline timeline;
  // The stage's inclinometer read at the pose (x, y, deg; inclinometer.h), when it was read.
  std::optional<Eigen::Vector2d> inclinometer_deg;
};

struct StationManifest {
  int schema_version = kStationSchemaVersion;
  std::string station_id;
  std::string created_utc;
  std::string updated_utc;
  std::string software_version;
  std::string rig_name;
  Calibration calibration;      // used for capture, and by default for processing
  std::vector<StagePose> plan;  // the capture plan, one pose per pair
  int image_width_px = 0;
  int image_height_px = 0;
  PixelFormat pixel_format = PixelFormat::kMono8;
  std::vector<PairRecord> pairs;  // completed pairs, any order, unique indices

  const PairRecord* FindPair(int index) const;
  bool Complete() const;  // every pose of the plan has its pair
  // Canonical file names of pair NN: "raw/pair_NN_left.png".
  static std::string ImageFileName(int index, Side side);
};

std::string ManifestToJson(const StationManifest& manifest);
// Parses and checks structure and values; errors name the field ("pairs[3].left.sha256").
// source names the file in messages.
Result<StationManifest> ManifestFromJson(const std::string& text, const std::string& source);

Result<StationManifest> LoadStationManifest(const std::string& station_dir);
// Atomic. Sets manifest->updated_utc (and created_utc on the first save).
Status SaveStationManifest(StationManifest* manifest, const std::string& station_dir);

std::string UtcNowIso8601();

// The capture timeline of the pairs that carry one: {"pairs": [{"pair", "move_s", ...}],
// "total_s": {field: sum}, "median_s": {field: median per pair}}; null when none does.
nlohmann::json CaptureTimelineJson(const std::vector<PairRecord>& pairs);

}  // namespace ts
