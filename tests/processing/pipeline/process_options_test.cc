// Each option is declared once (core/options.h): the check names the field by its
// path and gives its value, and the report's JSON holds every declared field with its default.
#include "processing/pipeline/process_options.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ts {
namespace {

TEST(ProcessOptions, OutOfRangeFieldsAreNamedWithTheirValue) {
  EXPECT_TRUE(ProcessOptions{}.Check(nullptr));
  ProcessOptions options;
  options.kriging.max_distance_m = 1e9;
  std::string why;
  EXPECT_FALSE(options.Check(&why));
  EXPECT_EQ(why, "kriging.max_distance_m must be in [0.1, 50] m, got 1e+09");
  options = {};
  options.matching.near_lsm.max_sigma_px = std::nan("");
  EXPECT_FALSE(options.Check(&why));
  EXPECT_NE(why.find("matching.near_lsm.max_sigma_px"), std::string::npos) << why;
  options = {};
  options.terrain_correction.density_kg_m3 = 1e308;
  EXPECT_FALSE(options.Check(&why));
  EXPECT_NE(why.find("terrain_correction.density_kg_m3"), std::string::npos) << why;
  options = {};
  options.horizon.edge_m = options.horizon.near_m / 2;  // in range, inconsistent
  EXPECT_FALSE(options.Check(&why));
  EXPECT_NE(why.find("near_m < edge_m"), std::string::npos) << why;
}

TEST(ProcessOptions, TheJsonHoldsTheValuesThatRun) {
  ProcessOptions options;
  options.kriging.variogram.max_lag_m = 17;
  const nlohmann::json j = ProcessOptionsToJson(options);
  EXPECT_EQ(j["kriging"]["variogram"]["max_lag_m"].get<double>(), 17);
  // The station presets, not the steps' own defaults.
  EXPECT_EQ(j["matching"]["min_spacing_m"].get<double>(), 0.2);
  EXPECT_EQ(j["ground"]["slope"].get<double>(), GroundFilterOptions::ForTripod().slope);
  EXPECT_NE(GroundFilterOptions::ForTripod().slope, GroundFilterOptions{}.slope);
  EXPECT_EQ(j["horizon"]["enabled"].get<bool>(), true);
}

}  // namespace
}  // namespace ts
