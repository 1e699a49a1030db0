#pragma once
// What `process` reads before it computes anything: the checked manifest, the calibration
// (and where it came from), the GCPs, and the images of a pair.
#include <optional>
#include <string>

#include "core/result.h"
#include "processing/dem/georeference.h"
#include "processing/geometry/calibration.h"
#include "processing/io/station_manifest.h"
#include "processing/matching/station_matching.h"

namespace ts {

struct StationInputs {
  std::string dir;
  StationManifest manifest;
  Calibration calibration;
  std::string calibration_source;  // the file given, or "station.json"
  std::string calibration_sha256;  // of the calibration as YAML: the same sum for the same one
  std::optional<Georeference> georeference;
};

// The manifest checked against the files (checksums; images are decoded per pair later), the
// calibration from calibration_file or else the manifest's, the GCPs if a file is given.
Result<StationInputs> LoadStationInputs(const std::string& station_dir,
                                        const std::string& calibration_file,
                                        const std::string& gcp_file);

// The decoded images of one committed pair, checked for size and pixel format.
Result<StereoPairImages> LoadPairImages(const StationInputs& inputs, const PairRecord& pair);

}  // namespace ts
