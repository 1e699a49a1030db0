#include "processing/pipeline/station_inputs.h"

#include "processing/io/calibration_yaml.h"
#include "processing/io/image_file.h"
#include "processing/io/sha256.h"
#include "processing/io/station_validator.h"

namespace ts {

Calibration StationStart(const Calibration& calibration, const StationManifest& manifest) {
  Calibration start = calibration;
  const StageKinematics& station = manifest.calibration.stage;
  start.stage.levelling_x_deg = station.levelling_x_deg;
  start.stage.levelling_y_deg = station.levelling_y_deg;
  start.stage.height_above_mark_m = station.height_above_mark_m;
  return start;
}

Result<StationInputs> LoadStationInputs(const std::string& dir, const std::string& calibration_file,
                                        const std::string& gcp_file,
                                        bool set_up_from_calibration_file) {
  StationValidationOptions validation;
  validation.decode_images = false;  // LoadPairImages decodes and checks each image once
  Result<StationManifest> manifest = ValidateStation(dir, validation);
  if (!manifest) return Error{manifest.error()};
  StationInputs in;
  in.dir = dir;
  in.manifest = std::move(*manifest);
  in.calibration = in.manifest.calibration;
  in.calibration_source = kManifestFileName;
  if (!calibration_file.empty()) {
    Result<Calibration> c = LoadCalibrationYaml(calibration_file);
    if (!c) return Error{c.error()};
    if (Status fits = CheckCalibrationFitsImages(*c, in.manifest, calibration_file); !fits)
      return Error{fits.error()};
    in.calibration = set_up_from_calibration_file ? *c : StationStart(*c, in.manifest);
    in.calibration_source = calibration_file;
    if (!set_up_from_calibration_file) in.calibration_source += " (levelling and height: station)";
  }
  in.calibration_sha256 = Sha256Hex(CalibrationToYaml(in.calibration));
  if (!gcp_file.empty()) {
    Result<Georeference> g = LoadGeoreference(gcp_file);
    if (!g) return Error{g.error()};
    in.georeference = *g;
  }
  return in;
}

Result<StereoPairImages> LoadPairImages(const StationInputs& in, const PairRecord& p) {
  const StationManifest& m = in.manifest;
  auto left =
      ReadMonoPng(in.dir + "/" + p.left.file, m.pixel_format, m.image_width_px, m.image_height_px);
  if (!left) return Error{left.error()};
  auto right =
      ReadMonoPng(in.dir + "/" + p.right.file, m.pixel_format, m.image_width_px, m.image_height_px);
  if (!right) return Error{right.error()};
  return StereoPairImages{p.index, p.readback.pan_deg, p.readback.tilt_deg, *left, *right};
}

}  // namespace ts
