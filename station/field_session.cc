#include "station/field_session.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "processing/io/station_manifest.h"
#include "station/commands.h"

namespace ts {
namespace {

FieldSessionFiles FromManifest(const std::string& dir) {
  const Result<StationManifest> manifest = LoadStationManifest(dir);
  if (!manifest) throw CommandError(manifest.error());
  FieldSessionFiles files;
  for (const PairRecord& p : manifest->pairs) {
    files.left.push_back((std::filesystem::path(dir) / p.left.file).string());
    files.right.push_back((std::filesystem::path(dir) / p.right.file).string());
    files.poses.push_back({p.readback.pan_deg, p.readback.tilt_deg, 0});
  }
  return files;
}

FieldSessionFiles FromSessionJson(const std::string& dir) {
  const std::string file = (std::filesystem::path(dir) / "session.json").string();
  std::ifstream in(file);
  if (!in)
    throw CommandError(dir +
                       ": neither station.json (capture --calibration field) nor "
                       "session.json (sim render --calibration field)");
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  if (j.is_discarded()) throw CommandError(file + ": not JSON");
  if (!j.contains("stage_poses") || !j["stage_poses"].is_array())
    throw CommandError(file + ": stage_poses: missing (not a field session)");
  FieldSessionFiles files;
  for (size_t k = 0; k < j["stage_poses"].size(); ++k) {
    const nlohmann::json& p = j["stage_poses"][k];
    const std::string field = file + ": stage_poses[" + std::to_string(k) + "]";
    if (!p.is_object() || !p.contains("image") || !p["image"].is_string() ||
        !p.contains("pan_deg") || !p["pan_deg"].is_number() || !p.contains("tilt_deg") ||
        !p["tilt_deg"].is_number())
      throw CommandError(field + ": needs image, pan_deg and tilt_deg");
    const std::string image = p["image"].get<std::string>();
    files.left.push_back((std::filesystem::path(dir) / "left" / image).string());
    files.right.push_back((std::filesystem::path(dir) / "right" / image).string());
    files.poses.push_back({p["pan_deg"].get<double>(), p["tilt_deg"].get<double>(), 0});
  }
  return files;
}

}  // namespace

FieldSessionFiles LoadFieldSessionFiles(const std::string& dir) {
  FieldSessionFiles files = std::filesystem::exists(std::filesystem::path(dir) / "station.json")
                                ? FromManifest(dir)
                                : FromSessionJson(dir);
  if (files.poses.empty()) throw CommandError(dir + ": the field session holds no pair");
  return files;
}

std::vector<FieldImage> LoadFieldImages(const std::vector<std::string>& files,
                                        const std::vector<ImageMarks>& marks,
                                        const CameraIntrinsics& camera,
                                        const std::string& camera_source) {
  std::vector<FieldImage> images;
  for (const std::string& file : files) {
    const cv::Mat grey = cv::imread(file, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw CommandError(file + ": not a readable image");
    if (grey.cols != camera.width_px || grey.rows != camera.height_px)
      throw CommandError(file + ": " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                         " pixels, the camera of " + camera_source + " has " +
                         std::to_string(camera.width_px) + "x" + std::to_string(camera.height_px));
    FieldImage image{file, {}, {}};
    grey.convertTo(image.image, CV_32FC1, 1.0 / 255.0);
    if (const ImageMarks* m = MarksOfImage(marks, file)) image.marks = m->marks;
    images.push_back(std::move(image));
  }
  return images;
}

FieldSessionInputs SimulatedFieldSession(const std::string& dir) {
  return {dir,
          dir + "/left/*.png",
          dir + "/right/*.png",
          dir + "/field.yaml",
          dir + "/marks.yaml",
          dir + "/design.yaml"};
}

std::vector<std::vector<std::string>> FieldCalibrationCommands(const FieldSessionInputs& session,
                                                               const std::string& cameras,
                                                               const std::string& out) {
  return {{"calibrate", "stereo", "--left", session.left_images, "--right", session.right_images,
           "--control-field", session.field, "--marks", session.marks, "--start", session.design,
           "--stage-from", session.design, "--out", cameras},
          {"calibrate", "rig", "--field-session", session.dir, "--control-field", session.field,
           "--marks", session.marks, "--calibration", cameras, "--out", out}};
}

}  // namespace ts
