#include "processing/io/station_manifest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "tests/common/station_fixture.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using nlohmann::json;

TEST(StationManifest, RoundTripsThroughJson) {
  testing::TempDir dir;
  const StationManifest m = testing::MakeStation(dir.path().string(), 12, 3);
  const Result<StationManifest> back = LoadStationManifest(dir.path().string());
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back->station_id, "TEST-001");
  EXPECT_EQ(back->plan.size(), 12u);
  ASSERT_EQ(back->pairs.size(), 3u);
  EXPECT_EQ(back->pairs[2].left.file, "raw/pair_02_left.png");
  EXPECT_EQ(back->pairs[2].right.sha256, m.pairs[2].right.sha256);
  EXPECT_DOUBLE_EQ(back->pairs[1].readback.pan_deg, 30.001);
  EXPECT_DOUBLE_EQ(back->calibration.rig.left.principal_distance_px, 80.0);
  EXPECT_FALSE(back->created_utc.empty());
  EXPECT_FALSE(back->Complete());
  EXPECT_NE(back->FindPair(2), nullptr);
  EXPECT_EQ(back->FindPair(3), nullptr);
  EXPECT_FALSE(back->pairs[0].inclinometer_deg);  // not read: none
  // Serialising again gives the same document.
  EXPECT_EQ(ManifestToJson(*back), ManifestToJson(*LoadStationManifest(dir.path().string())));
}

// The capture timeline goes with its pair (a resume keeps it); a pair without one (a rendered
// station) has none, and the report's timeline holds only the pairs that have one.
// A pair's inclinometer reading, when the capture read one, round-trips to the digit.
TEST(StationManifest, APairsInclinometerReadingRoundTrips) {
  testing::TempDir dir;
  StationManifest m = testing::MakeStation(dir.path().string(), 12, 3);
  m.pairs[1].inclinometer_deg = Eigen::Vector2d(0.123456789, -0.0205);
  ASSERT_TRUE(SaveStationManifest(&m, dir.path().string()).ok());
  const Result<StationManifest> back = LoadStationManifest(dir.path().string());
  ASSERT_TRUE(back.ok()) << back.error();
  ASSERT_TRUE(back->pairs[1].inclinometer_deg);
  EXPECT_EQ(*back->pairs[1].inclinometer_deg, Eigen::Vector2d(0.123456789, -0.0205));
  EXPECT_FALSE(back->pairs[0].inclinometer_deg);
}

TEST(StationManifest, CaptureTimelineRoundTripsAndSums) {
  testing::TempDir dir;
  StationManifest m = testing::MakeStation(dir.path().string(), 12, 3);
  m.pairs[0].timeline = {0.8, 0.2, 0.5, 0.09, 1, 0.001, 0.1, 1.1};
  m.pairs[2].timeline = {0.6, 0.2, 0.7, 0.11, 2, 0.003, 0.3, 1.3};
  ASSERT_TRUE(SaveStationManifest(&m, dir.path().string()).ok());
  const Result<StationManifest> back = LoadStationManifest(dir.path().string());
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_DOUBLE_EQ(back->pairs[2].timeline.trigger_to_frame_s, 0.11);
  EXPECT_EQ(back->pairs[2].timeline.triggers, 2);
  EXPECT_TRUE(std::isnan(back->pairs[1].timeline.move_s));
  const json t = CaptureTimelineJson(back->pairs);
  ASSERT_EQ(t["pairs"].size(), 2u);
  EXPECT_EQ(t["pairs"][1]["pair"], 2);
  EXPECT_DOUBLE_EQ(t["total_s"]["stage_wait_s"].get<double>(), 1.2);
  EXPECT_DOUBLE_EQ(t["total_s"]["write_s"].get<double>(), 0.4);
  EXPECT_TRUE(CaptureTimelineJson({back->pairs[1]}).is_null());
}

TEST(StationManifest, CanonicalImageNames) {
  EXPECT_EQ(StationManifest::ImageFileName(7, Side::kRight), "raw/pair_07_right.png");
  EXPECT_EQ(StationManifest::ImageFileName(11, Side::kLeft), "raw/pair_11_left.png");
}

struct Mutation {
  const char* name;
  void (*apply)(json& doc);
  const char* expect;
};

void PrintTo(const Mutation& m, std::ostream* os) { *os << m.name; }

class StationManifestBad : public ::testing::TestWithParam<Mutation> {};

TEST_P(StationManifestBad, NamesTheField) {
  testing::TempDir dir;
  const StationManifest m = testing::MakeStation(dir.path().string(), 4, 2);
  json doc = json::parse(ManifestToJson(m));
  GetParam().apply(doc);
  const Result<StationManifest> r = ManifestFromJson(doc.dump(), "S/station.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().rfind("S/station.json: ", 0), 0u) << r.error();
  EXPECT_NE(r.error().find(GetParam().expect), std::string::npos) << r.error();
}

INSTANTIATE_TEST_SUITE_P(
    Cases, StationManifestBad,
    ::testing::Values(
        Mutation{"version", [](json& d) { d["schema_version"] = 2; },
                 "schema_version: unsupported version 2"},
        Mutation{"schema", [](json& d) { d["schema"] = "other"; }, "schema: must be"},
        Mutation{"missing_sha", [](json& d) { d["pairs"][1]["left"].erase("sha256"); },
                 "pairs[1].left.sha256: missing"},
        Mutation{"bad_sha", [](json& d) { d["pairs"][0]["right"]["sha256"] = "xyz"; },
                 "pairs[0].right.sha256: must be 64 lower-case hex digits"},
        Mutation{"traversal",
                 [](json& d) { d["pairs"][0]["left"]["file"] = "raw/../../etc/passwd"; },
                 "pairs[0].left.file: must be a relative path inside raw/"},
        Mutation{"duplicate", [](json& d) { d["pairs"][1]["index"] = 0; },
                 "pairs[1].index: pair 0 recorded twice"},
        Mutation{"outside_plan", [](json& d) { d["pairs"][1]["index"] = 9; },
                 "pair 9 is not in the capture plan"},
        Mutation{"pan_type", [](json& d) { d["pairs"][0]["commanded"]["pan_deg"] = "north"; },
                 "pairs[0].commanded.pan_deg: must be a number"},
        Mutation{"format", [](json& d) { d["image"]["pixel_format"] = "RGB8"; },
                 "image.pixel_format: unknown pixel format"},
        Mutation{"calibration",
                 [](json& d) { d["calibration"]["cameras"]["left"]["width_px"] = -3; },
                 "calibration.cameras.left.width_px: must be in"},
        Mutation{"exposure", [](json& d) { d["pairs"][0]["exposure_us"] = 0; },
                 "pairs[0].exposure_us: must be positive"},
        Mutation{"timeline",
                 [](json& d) {
                   d["pairs"][1]["timeline"] = {{"write_s", -1}};
                 },
                 "pairs[1].timeline.write_s: must not be negative"},
        Mutation{"inclinometer_missing_y",
                 [](json& d) {
                   d["pairs"][1]["inclinometer_deg"] = {{"x", 0.1}};
                 },
                 "pairs[1].inclinometer_deg.y: missing"},
        Mutation{"inclinometer_past_90",
                 [](json& d) {
                   d["pairs"][1]["inclinometer_deg"] = {{"x", 91}, {"y", 0}};
                 },
                 "pairs[1].inclinometer_deg.x: an inclinometer reading must be within 90 deg"},
        Mutation{"not_object", [](json& d) { d = json::array(); }, "document: must be an object"},
        Mutation{"readback_1e300", [](json& d) { d["pairs"][1]["readback"]["pan_deg"] = 1e300; },
                 "pairs[1].readback.pan_deg: must be within 360 deg"},
        Mutation{"tilt_past_zenith", [](json& d) { d["capture_plan"][2]["tilt_deg"] = -135.0; },
                 "capture_plan[2].tilt_deg: must be within 90 deg"},
        Mutation{"baseline", [](json& d) { d["calibration"]["stereo"]["baseline_m"] = 1e-300; },
                 "calibration.stereo: baseline_m must be 0.01 to 10 m"},
        Mutation{"500_poses",
                 [](json& d) {
                   for (int i = 0; i < 500; ++i) d["capture_plan"].push_back(d["capture_plan"][0]);
                 },
                 "capture_plan: 504 poses, more than the 200 a station may have"}),
    [](const ::testing::TestParamInfo<Mutation>& info) { return std::string(info.param.name); });

TEST(StationManifest, TruncatedJsonIsReportedWithItsPosition) {
  testing::TempDir dir;
  const StationManifest m = testing::MakeStation(dir.path().string(), 4, 2);
  const std::string text = ManifestToJson(m);
  for (size_t cut : {size_t{0}, size_t{1}, text.size() / 3, text.size() - 3}) {
    const Result<StationManifest> r = ManifestFromJson(text.substr(0, cut), "S/station.json");
    ASSERT_FALSE(r.ok()) << cut;
    EXPECT_NE(r.error().find("S/station.json: malformed or truncated JSON at byte"),
              std::string::npos)
        << r.error();
  }
}

}  // namespace
}  // namespace ts
