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

}  // namespace
}  // namespace ts
