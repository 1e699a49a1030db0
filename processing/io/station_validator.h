#pragma once
// Checks a station directory against its manifest and reports the first problem, naming the
// file and the field: missing or malformed manifest, wrong schema version, missing image,
// checksum mismatch, image of the wrong size or pixel format.
#include <string>

#include "core/result.h"
#include "processing/io/station_manifest.h"

namespace ts {

struct StationValidationOptions {
  bool require_complete = false;  // every pose of the capture plan must have its pair
  bool decode_images = true;      // decode each PNG and check size and format (slower)
};

// The images of one pair, as ValidateStation checks them (present, checksum, and with
// decode_images the size and pixel format); errors name `field` ("pairs[3]").
Status CheckPairImages(const std::string& station_dir, const StationManifest& manifest,
                       const PairRecord& pair, const std::string& field,
                       const StationValidationOptions& options = {});

// A calibration is of the station's cameras as they were read out: each camera's image size
// is the station's (a calibration of another sensor, or of a binned readout, would be used
// without a word). source names the calibration in the error.
Status CheckCalibrationFitsImages(const Calibration& calibration, const StationManifest& manifest,
                                  const std::string& source);

// The manifest when everything checks out (also its own calibration against its images).
Result<StationManifest> ValidateStation(const std::string& station_dir,
                                        const StationValidationOptions& options = {});

}  // namespace ts
