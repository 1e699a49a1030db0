// The command line itself, before any command runs.
#include <gtest/gtest.h>

#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using testing::RunCommand;

// A word that is no command is named, with the commands there are: CLI11's own "A subcommand
// is required" did not say which word it had not understood.
TEST(CommandLine, AWordThatIsNoCommandIsNamed) {
  for (const std::string args : {"frobnicate", "-v frobnicate"}) {
    const auto r = RunCommand(std::string(TS_TOPOSTATION_EXE) + " " + args + " 2>&1");
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_NE(r.out.find("topostation: no command 'frobnicate' (commands: accuracy, validate"),
              std::string::npos)
        << r.out;
  }
  const auto none = RunCommand(std::string(TS_TOPOSTATION_EXE) + " 2>&1");
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.out.find("A subcommand is required"), std::string::npos) << none.out;
}

}  // namespace
}  // namespace ts
