#include "station/daemon/access_token.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "tests/common/temp_dir.h"

namespace ts::daemon {
namespace {

TEST(AccessToken, MadeAtFirstStartAs256BitsOnlyItsOwnerMayReadAndKept) {
  testing::TempDir dir;
  const std::string file = dir / "state/token";
  const Result<std::string> first = LoadOrCreateToken(file);
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first->size(), 64u);  // 32 bytes in hex
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600);
  const Result<std::string> again = LoadOrCreateToken(file);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(*again, *first);
  testing::TempDir other;
  EXPECT_NE(*LoadOrCreateToken(other / "token"), *first);
}

TEST(AccessToken, AFileOthersMayReadOrNotATokenIsRefusedByName) {
  testing::TempDir dir;
  const std::string file = dir / "token";
  ASSERT_TRUE(LoadOrCreateToken(file).ok());
  ::chmod(file.c_str(), 0644);
  const Result<std::string> open = LoadOrCreateToken(file);
  ASSERT_FALSE(open.ok());
  EXPECT_NE(open.error().find("0644"), std::string::npos) << open.error();
  std::ofstream(dir / "short") << "abc\n";
  ::chmod((dir / "short").c_str(), 0600);
  EXPECT_FALSE(LoadOrCreateToken(dir / "short").ok());
}

TEST(AccessToken, OnlyTheWholeTokenMatches) {
  const std::string token(64, 'a');
  EXPECT_TRUE(TokenMatches(token, token));
  EXPECT_FALSE(TokenMatches(token.substr(0, 63), token));
  EXPECT_FALSE(TokenMatches(token + "a", token));
  EXPECT_FALSE(TokenMatches("", token));
  EXPECT_FALSE(TokenMatches(std::string(63, 'a') + "b", token));
}

TEST(AuthThrottle, AClientThatKeepsGuessingWaitsLongerEachTime) {
  AuthThrottle t;
  const auto t0 = AuthThrottle::Clock::now();
  for (int i = 0; i < AuthThrottle::kFreeFailures - 1; ++i) t.Failed("10.0.0.9", t0);
  EXPECT_EQ(t.WaitSeconds("10.0.0.9", t0), 0);
  t.Failed("10.0.0.9", t0);
  EXPECT_EQ(t.WaitSeconds("10.0.0.9", t0), 1);
  t.Failed("10.0.0.9", t0);
  EXPECT_EQ(t.WaitSeconds("10.0.0.9", t0), 2);
  for (int i = 0; i < 20; ++i) t.Failed("10.0.0.9", t0);
  EXPECT_EQ(t.WaitSeconds("10.0.0.9", t0), 60);
  EXPECT_EQ(t.WaitSeconds("10.0.0.9", t0 + std::chrono::seconds(61)), 0);
  EXPECT_EQ(t.WaitSeconds("10.0.0.8", t0), 0);  // another client is not slowed
  t.Succeeded("10.0.0.9");
  EXPECT_EQ(t.WaitSeconds("10.0.0.9", t0), 0);
}

}  // namespace
}  // namespace ts::daemon
