#include "processing/io/station_validator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>

#include "processing/io/atomic_file.h"
#include "processing/io/sha256.h"
#include "tests/common/station_fixture.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

class StationValidator : public ::testing::Test {
 protected:
  void SetUp() override { manifest_ = testing::MakeStation(station(), 3, 2); }
  std::string station() const { return dir_.path().string(); }
  std::string File(const std::string& name) const { return dir_ / name; }
  // Replaces an image and records its new checksum, so only the image itself is wrong.
  void ReplaceImage(int pair, const cv::Mat& image) {
    ImageRecord& r = manifest_.pairs[pair].left;
    r.sha256 = *WritePngAtomically(image, File(r.file));
    ASSERT_TRUE(SaveStationManifest(&manifest_, station()).ok());
  }
  std::string Error(const StationValidationOptions& options = {}) const {
    const Result<StationManifest> r = ValidateStation(station(), options);
    return r.ok() ? std::string() : r.error();
  }

  testing::TempDir dir_;
  StationManifest manifest_;
};

TEST_F(StationValidator, AcceptsAValidStation) {
  EXPECT_EQ(Error(), "");
  // Not complete: the plan has three poses and two pairs are captured.
  EXPECT_NE(Error({.require_complete = true}).find("pair 2 of 3 not captured"), std::string::npos);
}

TEST_F(StationValidator, MissingImage) {
  std::filesystem::remove(File("raw/pair_01_right.png"));
  const std::string e = Error();
  EXPECT_NE(e.find("station.json: pairs[1].right: missing image"), std::string::npos) << e;
  EXPECT_NE(e.find("raw/pair_01_right.png"), std::string::npos) << e;
}

TEST_F(StationValidator, ChecksumMismatch) {
  std::ofstream(File("raw/pair_00_left.png"), std::ios::app) << "x";
  EXPECT_NE(Error().find("pairs[0].left: checksum mismatch"), std::string::npos) << Error();
}

TEST_F(StationValidator, ImageOfTheWrongSize) {
  ReplaceImage(0, cv::Mat(16, 32, CV_8UC1, cv::Scalar(9)));
  EXPECT_NE(Error().find("image is 32x16, manifest says 64x48"), std::string::npos) << Error();
  // Without decoding the images the size problem is not seen.
  EXPECT_EQ(Error({.decode_images = false}), "");
}

TEST_F(StationValidator, ImageOfTheWrongPixelFormat) {
  ReplaceImage(1, cv::Mat(48, 64, CV_16UC1, cv::Scalar(900)));
  EXPECT_NE(Error().find("expected Mono8 single-channel image"), std::string::npos) << Error();
}

TEST_F(StationValidator, CorruptImageData) {
  const std::string path = File(manifest_.pairs[0].left.file);
  std::string bytes = *ReadWholeFile(path);
  bytes.resize(bytes.size() / 2);  // a torn PNG
  ASSERT_TRUE(WriteFileAtomically(path, bytes).ok());
  manifest_.pairs[0].left.sha256 = *Sha256OfFile(path);
  ASSERT_TRUE(SaveStationManifest(&manifest_, station()).ok());
  EXPECT_NE(Error().find("not a readable PNG image"), std::string::npos) << Error();
}

TEST_F(StationValidator, MissingOrTruncatedManifest) {
  const std::string manifest = File("station.json");
  const std::string text = *ReadWholeFile(manifest);
  ASSERT_TRUE(WriteFileAtomically(manifest, text.substr(0, text.size() / 2)).ok());
  EXPECT_NE(Error().find("station.json: malformed or truncated JSON"), std::string::npos);
  std::filesystem::remove(manifest);
  EXPECT_NE(Error().find("station.json: missing manifest"), std::string::npos) << Error();
  EXPECT_NE(ValidateStation(File("nothing-here")).error().find("not a station directory"),
            std::string::npos);
}

}  // namespace
}  // namespace ts
