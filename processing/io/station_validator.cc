#include "processing/io/station_validator.h"

#include <algorithm>
#include <filesystem>

#include "processing/io/image_file.h"
#include "processing/io/sha256.h"

namespace ts {
namespace {

Status CheckImage(const std::string& station_dir, const StationManifest& m, const ImageRecord& r,
                  const std::string& field, const StationValidationOptions& options) {
  const std::string path = (std::filesystem::path(station_dir) / r.file).string();
  const std::string where = station_dir + "/" + kManifestFileName + ": " + field + ": ";
  if (!std::filesystem::is_regular_file(path)) return Error{where + "missing image " + path};
  // Through every link and "..": a station is the files in its directory, nothing outside.
  std::error_code ec;
  const std::filesystem::path real = std::filesystem::canonical(path, ec);
  const std::filesystem::path home = std::filesystem::canonical(station_dir, ec);
  const auto [outside, _] = std::mismatch(home.begin(), home.end(), real.begin(), real.end());
  if (ec || outside != home.end())
    return Error{where + path + " lies outside the station directory (" + real.string() + ")"};
  const Result<std::string> sha = Sha256OfFile(path);
  if (!sha) return Error{where + sha.error()};
  if (*sha != r.sha256) return Error{where + "checksum mismatch for " + path};
  // By content, always: a checksum says the file is the one written, not that it is a PNG.
  if (Status header = CheckMonoPngHeader(path, m.pixel_format, m.image_width_px, m.image_height_px);
      !header)
    return Error{where + header.error()};
  if (options.decode_images) {
    const Result<cv::Mat> image =
        ReadMonoPng(path, m.pixel_format, m.image_width_px, m.image_height_px);
    if (!image) return Error{where + image.error()};
  }
  return {};
}

}  // namespace

Status CheckPairImages(const std::string& station_dir, const StationManifest& m,
                       const PairRecord& pair, const std::string& field,
                       const StationValidationOptions& options) {
  if (Status s = CheckImage(station_dir, m, pair.left, field + ".left", options); !s) return s;
  return CheckImage(station_dir, m, pair.right, field + ".right", options);
}

Status CheckCalibrationFitsImages(const Calibration& calibration, const StationManifest& manifest,
                                  const std::string& source) {
  for (const auto& [name, camera] :
       {std::pair<const char*, const CameraIntrinsics&>{"left", calibration.rig.left},
        {"right", calibration.rig.right}})
    if (camera.width_px != manifest.image_width_px || camera.height_px != manifest.image_height_px)
      return Error{source + ": cameras." + name + " is of a " + std::to_string(camera.width_px) +
                   " x " + std::to_string(camera.height_px) + " px image, the station's are " +
                   std::to_string(manifest.image_width_px) + " x " +
                   std::to_string(manifest.image_height_px) +
                   ": a calibration of another camera or readout"};
  return {};
}

Result<StationManifest> ValidateStation(const std::string& station_dir,
                                        const StationValidationOptions& options) {
  if (!std::filesystem::is_directory(station_dir))
    return Error{station_dir + ": not a station directory"};
  Result<StationManifest> manifest = LoadStationManifest(station_dir);
  if (!manifest) return manifest;
  const StationManifest& m = *manifest;
  if (Status s = CheckCalibrationFitsImages(
          m.calibration, m, station_dir + "/" + kManifestFileName + ": calibration");
      !s)
    return Error{s.error()};
  for (size_t i = 0; i < m.pairs.size(); ++i) {
    const std::string field = "pairs[" + std::to_string(i) + "]";
    if (Status s = CheckPairImages(station_dir, m, m.pairs[i], field, options); !s)
      return Error{s.error()};
  }
  if (options.require_complete) {
    for (size_t i = 0; i < m.plan.size(); ++i) {
      if (!m.FindPair(static_cast<int>(i)))
        return Error{station_dir + "/" + kManifestFileName + ": pairs: pair " + std::to_string(i) +
                     " of " + std::to_string(m.plan.size()) + " not captured"};
    }
  }
  return manifest;
}

}  // namespace ts
