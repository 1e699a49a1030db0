// `topostation sim serve` as a user runs it: one JSON line when ready, the stage answering at
// the printed endpoint, the truth directory written, and a clean exit on SIGTERM.
#include <gtest/gtest.h>
#include <modbus/modbus.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/stage_registers.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

struct Child {
  pid_t pid = -1;
  FILE* out = nullptr;
};

Child Spawn(const std::vector<std::string>& args) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return {};
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(pipe_fds[1], STDOUT_FILENO);
    ::close(pipe_fds[0]);
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(pipe_fds[1]);
  return {pid, ::fdopen(pipe_fds[0], "r")};
}

TEST(SimServeCommand, ReadyLineEndpointsAndCleanShutdown) {
  testing::TempDir dir;
  Child child = Spawn({TS_TOPOSTATION_EXE, "sim", "serve", "--scene", "flat", "--truth",
                       dir / "truth", "--stage-port", "15140"});
  ASSERT_GT(child.pid, 0);
  char line[4096] = {};
  ASSERT_NE(std::fgets(line, sizeof(line), child.out), nullptr);
  const nlohmann::json ready = nlohmann::json::parse(line);
  EXPECT_TRUE(ready.at("ready").get<bool>());
  EXPECT_EQ(ready.at("stage_tcp"), "127.0.0.1:15140");
  EXPECT_EQ(ready.at("left_camera").at("serial"), "TS-SIM-L");
  EXPECT_EQ(ready.at("right_camera").at("address"), "127.0.0.2");
  EXPECT_TRUE(std::filesystem::exists(ready.at("stage_rtu").get<std::string>()));
  EXPECT_TRUE(std::filesystem::exists(dir / "truth/dem.tif"));

  modbus_t* ctx = modbus_new_tcp("127.0.0.1", 15140);
  modbus_set_slave(ctx, 1);
  ASSERT_EQ(modbus_connect(ctx), 0);
  uint16_t model = 0;
  EXPECT_EQ(modbus_read_registers(ctx, stage_registers::kModelId, 1, &model), 1);
  EXPECT_EQ(model, stage_registers::kModel);
  modbus_close(ctx);
  modbus_free(ctx);

  ASSERT_EQ(::kill(child.pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child.pid, &status, 0), child.pid);
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  std::fclose(child.out);
}

TEST(SimServeCommand, UnknownFaultIsOneClearError) {
  const auto r = testing::RunCommand(std::string(TS_TOPOSTATION_EXE) +
                                     " sim serve --truth /tmp/x --faults gvsp-lost=0.1 2>&1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.out.rfind("topostation: --faults: unknown fault 'gvsp-lost'", 0), 0u) << r.out;
}

}  // namespace
}  // namespace ts
