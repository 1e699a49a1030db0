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
//
// The levelling and the height above the mark belong to the station, not to the rig: a
// calibration file describes the rig (and carries the levelling of whichever station it was
// made at), so they are taken from the manifest (the inclinometer's reading at capture, the
// height measured there), unless set_up_from_calibration_file says the file was written for
// this very station (the simulator's truth).
Result<StationInputs> LoadStationInputs(const std::string& station_dir,
                                        const std::string& calibration_file,
                                        const std::string& gcp_file,
                                        bool set_up_from_calibration_file = false);

// The calibration's rig with the manifest's levelling and height above the mark.
Calibration StationStart(const Calibration& calibration, const StationManifest& manifest);

// The decoded images of one committed pair, checked for size and pixel format.
Result<StereoPairImages> LoadPairImages(const StationInputs& inputs, const PairRecord& pair);

}  // namespace ts
