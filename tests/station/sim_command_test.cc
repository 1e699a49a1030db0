// `topostation sim render` refuses bad epoch options with one clear line, before rendering.
#include <gtest/gtest.h>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using testing::RunCommand;

TEST(SimCommand, BadEpochOptionsGiveOneClearError) {
  testing::TempDir dir;
  auto error_of = [&](const std::string& options) {
    const auto r = RunCommand(std::string(TS_TOPOSTATION_EXE) + " sim render --scene flat --out " +
                              (dir / "s") + " --truth " + (dir / "t") + " " + options + " 2>&1");
    EXPECT_NE(r.exit_code, 0) << r.out;
    return r.out;
  };
  EXPECT_NE(error_of("--subsidence 10,0,3").find("X,Y,RADIUS,DEPTH"), std::string::npos);
  EXPECT_NE(error_of("--subsidence 2,0,3,0.5").find("clear of the station mark"),
            std::string::npos);
  EXPECT_NE(error_of("--subsidence 20,0,3,-1").find("depth"), std::string::npos);
  EXPECT_NE(error_of("--epoch 0").find("epoch"), std::string::npos);
  EXPECT_NE(error_of("--sun 90,1").find("elevation"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "s/station.json"));
}

}  // namespace
}  // namespace ts
