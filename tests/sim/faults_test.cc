#include "sim/faults.h"

#include <gtest/gtest.h>

namespace ts::sim {
namespace {

TEST(Faults, ParsesEveryKind) {
  const Result<SimFaults> f = ParseFaults(
      "gvsp-loss=0.01,camera-gone=right:after=5:for=10,stage-stall=pan:after=3,"
      "stage-alarm=tilt:after=2,modbus-crc=0.05,modbus-drop=0.02");
  ASSERT_TRUE(f.ok()) << f.error();
  EXPECT_DOUBLE_EQ(f->gvsp_loss, 0.01);
  ASSERT_TRUE(f->camera_gone);
  EXPECT_EQ(f->camera_gone->side, Side::kRight);
  EXPECT_DOUBLE_EQ(f->camera_gone->after_s, 5);
  EXPECT_DOUBLE_EQ(f->camera_gone->for_s, 10);
  ASSERT_TRUE(f->stage_stall && f->stage_alarm);
  EXPECT_TRUE(f->stage_stall->pan);
  EXPECT_EQ(f->stage_stall->after_moves, 3);
  EXPECT_FALSE(f->stage_alarm->pan);
  EXPECT_DOUBLE_EQ(f->modbus_crc, 0.05);
  EXPECT_DOUBLE_EQ(f->modbus_drop, 0.02);
  EXPECT_TRUE(ParseFaults("").ok());
}

TEST(Faults, RejectsWhatItDoesNotKnow) {
  const std::pair<const char*, const char*> cases[] = {
      {"gvsp-los=0.1", "unknown fault 'gvsp-los'"},
      {"gvsp-loss=lots", "gvsp-loss: 'lots' must be a number"},
      {"modbus-crc=1.5", "modbus-crc: '1.5' must be a number in [0, 0.9]"},
      {"camera-gone=middle:after=1:for=1", "side must be left or right"},
      {"camera-gone=left:after=1", "missing 'for='"},
      {"stage-stall=roll:after=1", "axis must be pan or tilt"},
      {"stage-alarm=pan:when=3", "unknown part 'when=3'"},
      {"modbus-drop", "'modbus-drop' is not key=value"},
  };
  for (const auto& [spec, expect] : cases) {
    const Result<SimFaults> f = ParseFaults(spec);
    ASSERT_FALSE(f.ok()) << spec;
    EXPECT_NE(f.error().find(expect), std::string::npos) << f.error();
    EXPECT_EQ(f.error().rfind("--faults: ", 0), 0u);
  }
}

}  // namespace
}  // namespace ts::sim
