// A calibration file describes the rig and carries the levelling of whichever station it was
// made at: `process` takes the levelling and the height above the mark from the station's own
// manifest, unless it is told the file was written for this very station.
#include "processing/pipeline/station_inputs.h"

#include <gtest/gtest.h>

#include "processing/io/calibration_yaml.h"
#include "tests/common/station_fixture.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

TEST(StationInputs, TheLevellingAndHeightAreTheStationsUnlessTheFileIsItsOwn) {
  testing::TempDir dir;
  const std::string station = dir / "st";
  StationManifest m = testing::MakeStation(station, 3, 3);
  m.calibration.stage.levelling_x_deg = 0.12;  // the inclinometer at this station
  m.calibration.stage.levelling_y_deg = -0.07;
  m.calibration.stage.height_above_mark_m = 1.48;
  ASSERT_TRUE(SaveStationManifest(&m, station).ok());
  // The rig calibrated at another station, set up another way.
  Calibration rig = m.calibration;
  rig.stage.levelling_x_deg = 0.5;
  rig.stage.levelling_y_deg = -0.3;
  rig.stage.height_above_mark_m = 1.71;
  rig.stage.tilt_zero_deg = 0.2;
  ASSERT_TRUE(SaveCalibrationYaml(rig, dir / "rig.yaml").ok());

  const Result<StationInputs> in = LoadStationInputs(station, dir / "rig.yaml", "");
  ASSERT_TRUE(in) << in.error();
  EXPECT_EQ(in->calibration.stage.levelling_x_deg, 0.12);
  EXPECT_EQ(in->calibration.stage.levelling_y_deg, -0.07);
  EXPECT_EQ(in->calibration.stage.height_above_mark_m, 1.48);
  EXPECT_EQ(in->calibration.stage.tilt_zero_deg, 0.2);  // the rig's own
  EXPECT_NE(in->calibration_source.find("levelling and height: station"), std::string::npos)
      << in->calibration_source;

  const Result<StationInputs> own = LoadStationInputs(station, dir / "rig.yaml", "", true);
  ASSERT_TRUE(own) << own.error();
  EXPECT_EQ(own->calibration.stage.levelling_x_deg, 0.5);
  EXPECT_EQ(own->calibration.stage.height_above_mark_m, 1.71);
  EXPECT_EQ(own->calibration_source, dir / "rig.yaml");
  EXPECT_NE(own->calibration_sha256, in->calibration_sha256);
}

// A calibration of another sensor (or of a binned readout) is refused, naming the file.
TEST(StationInputs, ACalibrationOfAnotherImageSizeIsRefused) {
  testing::TempDir dir;
  const std::string station = dir / "st";
  const StationManifest m = testing::MakeStation(station, 3, 3);
  Calibration other = m.calibration;
  other.rig.left.width_px = other.rig.right.width_px = m.image_width_px / 2;
  other.rig.left.height_px = other.rig.right.height_px = m.image_height_px / 2;
  other.rig.left.principal_point_x_px = other.rig.right.principal_point_x_px =
      0.25 * m.image_width_px;
  other.rig.left.principal_point_y_px = other.rig.right.principal_point_y_px =
      0.25 * m.image_height_px;
  other.rig.left.principal_distance_px /= 2;
  other.rig.right.principal_distance_px /= 2;
  ASSERT_TRUE(SaveCalibrationYaml(other, dir / "binned.yaml").ok());
  const Result<StationInputs> in = LoadStationInputs(station, dir / "binned.yaml", "");
  ASSERT_FALSE(in);
  EXPECT_NE(in.error().find(dir / "binned.yaml" + ": cameras.left is of a " +
                            std::to_string(m.image_width_px / 2) + " x "),
            std::string::npos)
      << in.error();
  EXPECT_NE(in.error().find("another camera or readout"), std::string::npos);
}

}  // namespace
}  // namespace ts
