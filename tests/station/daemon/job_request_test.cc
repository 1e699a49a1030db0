#include "station/daemon/job_request.h"

#include <gtest/gtest.h>

namespace ts::daemon {
namespace {

TEST(JobRequest, ASurveyTakesTheFieldsAGravityCrewRecords) {
  const Result<JobRequest> r =
      ParseJobRequest({{"kind", "survey"},
                       {"station", "G-0412"},
                       {"line", "L7"},
                       {"instrument_height_m", 1.52},
                       {"operator", "A. Surveyor"},
                       {"notes", "windy"},
                       {"gnss", {{"lat_deg", 47.1}, {"lon_deg", 8.3}, {"height_m", 512.0}}},
                       {"gcps", {{{"id", "p1"}, {"x", 1.0}, {"y", 2.0}, {"z", 3.0}}}}});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->kind, JobKind::kSurvey);
  EXPECT_EQ(r->station, "G-0412");
  EXPECT_EQ(r->instrument_height_m, 1.52);
  EXPECT_EQ(r->fields["line"], "L7");
  EXPECT_FALSE(r->fields.contains("kind"));
}

TEST(JobRequest, EachBadFieldIsNamed) {
  const nlohmann::json good = {{"kind", "survey"}, {"station", "S1"}, {"instrument_height_m", 1.5}};
  const std::pair<nlohmann::json, std::string> cases[] = {
      {{{"kind", "dance"}}, "kind"},
      {{{"station", "../../etc"}}, "station"},
      {{{"station", std::string(65, 's')}}, "station"},
      {{{"instrument_height_m", -1}}, "instrument_height_m"},
      {{{"instrument_height_m", "1.5"}}, "instrument_height_m"},
      {{{"instrument_height_m", 1e308}}, "instrument_height_m"},
      {{{"operator", std::string(3000, 'x')}}, "operator"},
      {{{"gnss", {{"lat_deg", 91}, {"lon_deg", 0}}}}, "gnss.lat_deg"},
      {{{"gnss", {{"lon_deg", 0}}}}, "gnss.lat_deg: missing"},
      {{{"gcps", {{{"id", "a/b"}, {"x", 0}, {"y", 0}, {"z", 0}}}}}, "gcps[0].id"},
      {{{"gcps", {{{"id", "a"}, {"x", 0}, {"y", 0}}}}}, "gcps[0].z"},
      {{{"single_row", 1}}, "single_row"},
      {{{"stations", "S2"}}, "stations: unknown field"},
  };
  for (const auto& [change, field] : cases) {
    nlohmann::json body = good;
    body.update(change);
    const Result<JobRequest> r = ParseJobRequest(body);
    ASSERT_FALSE(r.ok()) << body.dump();
    EXPECT_NE(r.error().find(field), std::string::npos) << r.error();
  }
  EXPECT_FALSE(ParseJobRequest({{"kind", "survey"}, {"station", "S1"}}).ok());  // no height
  EXPECT_FALSE(ParseJobRequest(nlohmann::json::array()).ok());
  EXPECT_TRUE(ParseJobRequest({{"kind", "process"}, {"station", "S1"}}).ok());
}

TEST(JobRequest, ACalibrationOfTheRigNamesItsStationsEachChecked) {
  const Result<JobRequest> r =
      ParseJobRequest({{"kind", "calibrate_rig"}, {"stations", {"S1", "S2"}}});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->kind, JobKind::kCalibrateRig);
  EXPECT_EQ(r->stations, (std::vector<std::string>{"S1", "S2"}));
  EXPECT_EQ(r->station, "S1");
  EXPECT_TRUE(
      ParseJobRequest({{"kind", "calibrate_rig"}, {"stations", {"S1"}}, {"refine_cameras", true}})
          .ok());
  const Result<JobRequest> not_a_flag =
      ParseJobRequest({{"kind", "calibrate_rig"}, {"stations", {"S1"}}, {"refine_cameras", "yes"}});
  ASSERT_FALSE(not_a_flag.ok());
  EXPECT_EQ(not_a_flag.error(), "refine_cameras: must be true or false");
  for (const nlohmann::json& bad :
       {nlohmann::json{{"kind", "calibrate_rig"}, {"stations", {"S1", "../x"}}},
        nlohmann::json{{"kind", "calibrate_rig"}, {"stations", nlohmann::json::array()}},
        nlohmann::json{{"kind", "calibrate_rig"}, {"stations", "S1"}}}) {
    const Result<JobRequest> refused = ParseJobRequest(bad);
    ASSERT_FALSE(refused.ok()) << bad.dump();
    EXPECT_NE(refused.error().find("stations"), std::string::npos) << refused.error();
  }
}

TEST(JobRequest, AFieldSessionTakesItsGridWithinTheStagesReach) {
  const Result<JobRequest> r = ParseJobRequest({{"kind", "capture_field"},
                                                {"station", "field-1"},
                                                {"field_pan_deg", 40},
                                                {"field_pans", 5}});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->kind, JobKind::kCaptureField);
  EXPECT_TRUE(UsesRig(r->kind));
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"field_tilt_deg", 40}, {"field_pans", 0}, {"field_tilts", 10}, {"station", "../f"}}) {
    nlohmann::json body = {{"kind", "capture_field"}, {"station", "f"}};
    body[key] = value;
    const Result<JobRequest> refused = ParseJobRequest(body);
    ASSERT_FALSE(refused.ok()) << body.dump();
    EXPECT_NE(refused.error().find(key), std::string::npos) << refused.error();
  }
}

// A field session's calibration: the field and the marks checked as their files are, a mark of
// a target the field lacks refused, each refusal naming the field.
TEST(JobRequest, AFieldCalibrationTakesTheFieldAndTheMarksCheckedAsTheirFilesAre) {
  nlohmann::json targets = nlohmann::json::array();
  for (int id = 101; id <= 106; ++id)
    targets.push_back({{"id", id},
                       {"x", id * 0.5},
                       {"y", 1.0},
                       {"z", 2.0},
                       {"sigma_m", 0.001},
                       {"diameter_m", 0.06}});
  const nlohmann::json marks = {
      {{"image", "raw/p0000_left.png"}, {"targets", {{{"id", 101}, {"x", 80.5}, {"y", 30.0}}}}}};
  const nlohmann::json good = {{"kind", "calibrate_field"},
                               {"session", "field-1"},
                               {"control_field", {{"version", 1}, {"targets", targets}}},
                               {"marks", marks}};
  const Result<JobRequest> r = ParseJobRequest(good);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->kind, JobKind::kCalibrateField);
  EXPECT_FALSE(UsesRig(r->kind));
  EXPECT_EQ(r->station, "field-1");
  EXPECT_EQ(r->fields["marks"], marks);
  auto refusal = [&](const std::string& key, const nlohmann::json& value) {
    nlohmann::json body = good;
    if (value.is_null())
      body.erase(key);
    else
      body[key] = value;
    const Result<JobRequest> refused = ParseJobRequest(body);
    return refused.ok() ? std::string("accepted") : refused.error();
  };
  EXPECT_EQ(refusal("session", "../x").rfind("session: ", 0), 0u);
  EXPECT_EQ(refusal("marks", nullptr), "marks: missing");
  EXPECT_EQ(refusal("control_field", nullptr), "control_field: missing");
  nlohmann::json twice = targets;
  twice[5]["id"] = 101;
  EXPECT_EQ(refusal("control_field", {{"version", 1}, {"targets", twice}})
                .rfind("control_field.targets[5].id: 101 twice", 0),
            0u);
  nlohmann::json five = targets;
  five.erase(5);
  EXPECT_EQ(refusal("control_field", {{"version", 1}, {"targets", five}})
                .rfind("control_field.targets: ", 0),
            0u);
  EXPECT_EQ(refusal("marks",
                    {{{"image", "a.png"}, {"targets", {{{"id", 101}, {"x", "left"}, {"y", 1}}}}}})
                .rfind("marks[0].targets[0].x: ", 0),
            0u);
  EXPECT_EQ(
      refusal("marks", {{{"image", "a.png"}, {"targets", {{{"id", 7}, {"x", 1}, {"y", 1}}}}}}),
      "marks[0].targets[0].id: 7 is not a target of control_field");
  EXPECT_EQ(refusal("extra", 1), "extra: unknown field");
}

TEST(JobRequest, ARetakeTakesThePosesAVerdictNamedWithinTheStagesReach) {
  const Result<JobRequest> r =
      ParseJobRequest({{"kind", "retake"},
                       {"station", "G-1"},
                       {"poses", {{{"pan_deg", 90}, {"tilt_deg", -12.7}}}}});
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r->kind, JobKind::kRetake);
  EXPECT_TRUE(UsesRig(r->kind));
  EXPECT_EQ(r->fields["poses"][0]["pan_deg"], 90);
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"poses", nlohmann::json::array()},
           {"poses", {{{"pan_deg", 90}}}},
           {"poses", {{{"pan_deg", 90}, {"tilt_deg", 40}}}},
           {"station", "../x"},
           {"instrument_height_m", 1.5}}) {
    nlohmann::json body = {
        {"kind", "retake"}, {"station", "G-1"}, {"poses", {{{"pan_deg", 0}, {"tilt_deg", 0}}}}};
    body[key] = value;
    const Result<JobRequest> refused = ParseJobRequest(body);
    ASSERT_FALSE(refused.ok()) << body.dump();
    EXPECT_NE(refused.error().find(key), std::string::npos) << refused.error();
  }
  // The survey's sigma wanted, checked.
  nlohmann::json survey = {{"kind", "survey"},
                           {"station", "S"},
                           {"instrument_height_m", 1.5},
                           {"required_sigma_mgal", 0.0}};
  const Result<JobRequest> zero = ParseJobRequest(survey);
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(zero.error().find("required_sigma_mgal"), std::string::npos) << zero.error();
  survey["required_sigma_mgal"] = 0.01;
  EXPECT_TRUE(ParseJobRequest(survey).ok());
}

}  // namespace
}  // namespace ts::daemon
