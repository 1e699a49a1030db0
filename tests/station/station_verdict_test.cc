// The operator's verdict from a terrain correction's ring and sector table: each answer, and
// the poses a retake would take, on tables built for it.
#include "station/station_verdict.h"

#include <gtest/gtest.h>

namespace ts {
namespace {

// 12 poses 30 deg apart at tilt -12, and upper poses at 90 and 120 deg.
std::vector<StagePose> Plan() {
  std::vector<StagePose> plan;
  for (int k = 0; k < 12; ++k) plan.push_back({30.0 * k, -12.0});
  plan.push_back({90.0, 8.0});
  plan.push_back({120.0, 8.0});
  return plan;
}

// Rings 0-2, 2-10, 10-20, 20-30 m; every sector covered with sigma `s` except one.
nlohmann::json Tc(double sigma, int ring, int sector, double coverage, double sector_sigma) {
  nlohmann::json rings = nlohmann::json::array();
  const double edges[] = {0, 2, 10, 20, 30};
  for (int r = 0; r < 4; ++r) {
    nlohmann::json sectors = nlohmann::json::array();
    for (int k = 0; k < 12; ++k) {
      const bool odd = r == ring && k == sector;
      sectors.push_back({{"bearing_deg", 30.0 * k},
                         {"coverage", odd ? coverage : 1.0},
                         {"seen", odd ? coverage : 1.0},
                         {"sigma_mgal", odd ? sector_sigma : 0.0005}});
    }
    rings.push_back({{"inner_m", edges[r]},
                     {"outer_m", edges[r + 1]},
                     {"coverage", r == ring ? (11 + coverage) / 12 : 1.0},
                     {"sectors", sectors}});
  }
  return {{"verdict", "usable"}, {"sigma_mgal", sigma}, {"rings", rings}};
}

TEST(StationVerdict, GoodWhenSigmaIsWithinWhatWasAsked) {
  const StationVerdict v = JudgeStation(Tc(0.008, 1, 3, 0.2, 0.006), Plan(), 0.01);
  EXPECT_EQ(v.verdict, "good");
  EXPECT_TRUE(v.retake.empty());
  EXPECT_NE(v.text.find("0.0080"), std::string::npos) << v.text;
}

TEST(StationVerdict, RetakesTheMainRowPoseTowardTheThinSectorOfANearRing) {
  const StationVerdict v = JudgeStation(Tc(0.012, 1, 3, 0.3, 0.009), Plan(), 0.01);
  EXPECT_EQ(v.verdict, "retake");
  ASSERT_EQ(v.retake.size(), 1u);
  EXPECT_EQ(v.retake[0].pan_deg, 90.0);
  EXPECT_EQ(v.retake[0].tilt_deg, -12.0);
  EXPECT_NE(v.text.find("2-10 m ring is 94 % covered, toward 90° only 30 % seen"),
            std::string::npos)
      << v.text;
  EXPECT_NE(v.text.find("retake the pose at 90°"), std::string::npos) << v.text;
}

TEST(StationVerdict, AFarRingIsRetakenWithTheUpperPoseToo) {
  const StationVerdict v = JudgeStation(Tc(0.015, 3, 4, 0.1, 0.012), Plan(), 0.01);
  EXPECT_EQ(v.verdict, "retake");
  ASSERT_EQ(v.retake.size(), 2u);
  EXPECT_EQ(v.retake[1].tilt_deg, 8.0);
  EXPECT_NE(v.text.find("the pose at 120° and the upper pose at 120°"), std::string::npos)
      << v.text;
}

TEST(StationVerdict, ASeenSectorNeedsNoRetake) {
  const StationVerdict v = JudgeStation(Tc(0.02, 2, 5, 1.0, 0.019), Plan(), 0.01);
  EXPECT_EQ(v.verdict, "as good as it gets");
  EXPECT_TRUE(v.retake.empty());
  EXPECT_NE(v.text.find("would not lower"), std::string::npos) << v.text;
}

// Ground under the rig no pose sees: a retake cannot help, a tape can.
TEST(StationVerdict, GroundNearerThanAnyViewIsMeasuredByHandNotRetaken) {
  const StationVerdict v = JudgeStation(Tc(0.03, 0, 2, 0.0, 0.029), Plan(), 0.01, 2.4);
  EXPECT_EQ(v.verdict, "as good as it gets");
  EXPECT_TRUE(v.retake.empty());
  EXPECT_NE(v.text.find("0-2 m ring toward 60°, nearer than any view reaches (2.4 m)"),
            std::string::npos)
      << v.text;
  // The same ring within reach of the views: retaken.
  EXPECT_EQ(JudgeStation(Tc(0.03, 0, 2, 0.0, 0.029), Plan(), 0.01, 1.5).verdict, "retake");
}

// Most of sigma under the rig, where no view reaches; a far sector unseen besides: retaken
// when taking it again lowers sigma by a tenth or more, else not.
TEST(StationVerdict, ARetakeIsNamedWhenItLowersSigmaByATenth) {
  nlohmann::json tc = Tc(0.033, 3, 4, 0.1, 0.02);
  tc["rings"][0]["sectors"][2]["sigma_mgal"] = 0.025;
  tc["rings"][0]["sectors"][2]["seen"] = 0.0;
  const StationVerdict worth = JudgeStation(tc, Plan(), 0.01, 2.4);
  EXPECT_EQ(worth.verdict, "retake") << worth.text;
  ASSERT_EQ(worth.retake.size(), 2u);
  EXPECT_EQ(worth.retake[0].pan_deg, 120.0);
  tc["rings"][3]["sectors"][4]["sigma_mgal"] = 0.005;  // sqrt(0.033^2 - 0.005^2) = 0.0326
  const StationVerdict not_worth = JudgeStation(tc, Plan(), 0.01, 2.4);
  EXPECT_EQ(not_worth.verdict, "as good as it gets");
  EXPECT_TRUE(not_worth.retake.empty());
  EXPECT_NE(not_worth.text.find("0-2 m ring toward 60°, nearer than any view"), std::string::npos)
      << not_worth.text;
}

TEST(StationVerdict, UnusableNamesTheLeastSeenDirection) {
  nlohmann::json tc = Tc(0.0, 2, 7, 0.0, 0.0);
  tc["verdict"] = "unusable";
  tc["unusable_because"] = "only 8 % of the ground within 30 m was seen";
  const StationVerdict v = JudgeStation(tc, Plan(), 0.01);
  EXPECT_EQ(v.verdict, "unusable");
  ASSERT_EQ(v.retake.size(), 1u);
  EXPECT_EQ(v.retake[0].pan_deg, 210.0);
  EXPECT_NE(v.text.find("only 8 %"), std::string::npos) << v.text;
  EXPECT_EQ(JudgeStation(nullptr, Plan(), 0.01).verdict, "not processed");
  // A correction from before the sectors: no direction to name, and it says so.
  const StationVerdict old = JudgeStation(
      {{"verdict", "usable"}, {"sigma_mgal", 0.02}, {"rings", nlohmann::json::array()}}, Plan(),
      0.01);
  EXPECT_EQ(old.verdict, "as good as it gets");
  EXPECT_NE(old.text.find("process the station again"), std::string::npos) << old.text;
}

}  // namespace
}  // namespace ts
