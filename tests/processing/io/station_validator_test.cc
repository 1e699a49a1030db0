#include "processing/io/station_validator.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

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
  // The header says so: seen without decoding the images too.
  EXPECT_NE(Error({.decode_images = false}).find("image is 32x16"), std::string::npos);
}

// Checked by content before anything is decoded: a JPEG named .png (its checksum right), and
// a PNG whose header declares 30000 x 30000 (it was decoded in full, 940 MB, before its size
// was refused).
TEST_F(StationValidator, ImagesAreCheckedByContentBeforeDecoding) {
  const std::string path = File(manifest_.pairs[0].left.file);
  std::vector<uchar> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", cv::Mat(48, 64, CV_8UC1, cv::Scalar(50)), jpeg));
  ASSERT_TRUE(WriteFileAtomically(path, std::string(jpeg.begin(), jpeg.end())).ok());
  manifest_.pairs[0].left.sha256 = *Sha256OfFile(path);
  ASSERT_TRUE(SaveStationManifest(&manifest_, station()).ok());
  EXPECT_NE(Error({.decode_images = false}).find("not a PNG image by its content (a JPEG)"),
            std::string::npos)
      << Error();
  std::string huge = *ReadWholeFile(File(manifest_.pairs[1].left.file));
  for (int k : {16, 20}) huge.replace(k, 4, std::string("\x00\x00\x75\x30", 4));  // 30000
  ASSERT_TRUE(WriteFileAtomically(path, huge).ok());
  manifest_.pairs[0].left.sha256 = *Sha256OfFile(path);
  ASSERT_TRUE(SaveStationManifest(&manifest_, station()).ok());
  EXPECT_NE(Error().find("image is 30000x30000, manifest says 64x48"), std::string::npos)
      << Error();
}

// No path leaves the station: a raw/ that links elsewhere is refused, naming where it leads.
TEST_F(StationValidator, ImagesOutsideTheStationAreRefused) {
  testing::TempDir elsewhere;
  std::filesystem::rename(File("raw"), elsewhere / "raw");
  std::filesystem::create_directory_symlink(elsewhere / "raw", File("raw"));
  EXPECT_NE(Error().find("lies outside the station directory"), std::string::npos) << Error();
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
