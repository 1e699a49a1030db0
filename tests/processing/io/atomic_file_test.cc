#include "processing/io/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "processing/io/sha256.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

TEST(AtomicFile, WritesReadsAndReplaces) {
  testing::TempDir dir;
  const std::string path = dir / "a.txt";
  ASSERT_TRUE(WriteFileAtomically(path, "first version, longer than the second").ok());
  ASSERT_TRUE(WriteFileAtomically(path, "second").ok());
  const Result<std::string> text = ReadWholeFile(path);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(*text, "second");
  // No temporary file is left behind.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    ++files;
    EXPECT_FALSE(IsTemporaryName(entry.path().filename().string()));
  }
  EXPECT_EQ(files, 1);
}

TEST(AtomicFile, ReportsTheFileWhenTheFolderIsMissing) {
  testing::TempDir dir;
  const std::string path = dir / "no/such/folder/x.txt";
  const Status s = WriteFileAtomically(path, "x");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find(path), std::string::npos);
  EXPECT_FALSE(ReadWholeFile(path).ok());
}

TEST(Sha256, KnownDigests) {
  // FIPS 180-2 test vectors.
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  testing::TempDir dir;
  const std::string big(1 << 20, 'a');  // more than one read buffer
  ASSERT_TRUE(WriteFileAtomically(dir / "big", big).ok());
  const Result<std::string> sha = Sha256OfFile(dir / "big");
  ASSERT_TRUE(sha.ok());
  EXPECT_EQ(*sha, Sha256Hex(big));
  EXPECT_FALSE(Sha256OfFile(dir / "missing").ok());
}

}  // namespace
}  // namespace ts
