#include "sim/served_calibration.h"

#include <filesystem>
#include <memory>

#include "processing/io/station_manifest.h"

namespace ts::sim {
void ServeCalibrationTargets(const SimRig& rig, uint64_t seed, const ServedCalibration& served,
                             SimulatedCameraOptions* left, SimulatedCameraOptions* right) {
  if (served.kind.empty()) return;
  std::shared_ptr<const FieldSession> session;
  if (served.kind == "field")
    session = std::make_shared<const FieldSession>(PlanFieldSession(rig, seed, served.field));
  for (SimulatedCameraOptions* camera : {left, right}) {
    const Side side = camera->side;
    if (session) {
      const int supersampling = served.field.supersampling;
      camera->target_radiance = [&rig, session, side, supersampling](const StagePose& pose, int) {
        return RenderFieldView(rig, *session, side, pose, supersampling);
      };
      camera->target_views = 1;
      continue;
    }
    const BoardSessionOptions o = BoardSessionOf(served.kind, served.board);
    auto placements =
        std::make_shared<const std::vector<BoardPlacement>>(PlanBoardSession(rig, seed, o));
    auto charuco = std::make_shared<const cv::Mat>(CharucoImageOf(o));
    camera->target_radiance = [&rig, placements, charuco, side, o](const StagePose&, int view) {
      return RenderPlacementView(rig, (*placements)[view], side, o, *charuco);
    };
    camera->target_views = static_cast<int>(placements->size());
  }
}

Status WriteServedCalibrationTruth(const SimRig& rig, uint64_t seed,
                                   const ServedCalibration& served, const std::string& truth_dir) {
  namespace fs = std::filesystem;
  if (served.kind != "field") return {};
  const auto in = [&](const char* name) { return (fs::path(truth_dir) / name).string(); };
  FieldSession session = PlanFieldSession(rig, seed, served.field);
  for (size_t k = 0; k < session.marks.size(); ++k)
    session.marks[k].image = StationManifest::ImageFileName(static_cast<int>(k), Side::kLeft);
  if (Status s = SaveControlField(session.surveyed, in("field.yaml")); !s) return s;
  return SaveTargetMarks(session.marks, in("marks.yaml"));
}

}  // namespace ts::sim
