#pragma once
// The station-wide steps of `process`, after every pair has been matched into L (DESIGN.md
// "Processing pipeline"), each a function over the station's working state:
//   FilterHeightBlunders -> FindObjectsAlongSightLines -> FilterGroundPoints ->
//   RemoveUndersidePatches -> RemovePointsSeenThroughGround -> KrigeStationDem ->
//   LimitDemToHorizon -> KeepBelowSightLines -> WidenStdByGroundRoom -> AddSightTiltSigma ->
//   CorrectTerrain
// A step fills its StepSummary (counts, warnings) and returns false with summary->message on
// failure; processing code below may throw, which the StepRunner catches.
#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "processing/cloud/point_cloud.h"
#include "processing/dem/free_space.h"
#include "processing/dem/kriging.h"
#include "processing/gravity/terrain_correction.h"
#include "processing/pipeline/process_options.h"
#include "processing/pipeline/station_inputs.h"
#include "processing/pipeline/step.h"

namespace ts {

enum PointClass : uint8_t { kOutsideDem = 0, kBlunder = 1, kObject = 2, kGround = 3 };

// Everything the station-wide steps read and write, in the order they fill it.
struct StationWork {
  const StationInputs* inputs = nullptr;
  std::vector<StereoPairImages> pairs;        // in pair order: index and read-back, no images
  cv::Mat panorama;                           // products/panorama.png, drawn as the pairs came
  PointCloud cloud;                           // every intersected point, in L, in pair order
  std::map<int, Eigen::Vector3d> viewpoints;  // left camera centre per pair, in L
  Eigen::Vector3d station_viewpoint = Eigen::Vector3d::Zero();  // the cameras' mean centre
  std::vector<uint8_t> point_class;                             // PointClass, one per cloud point
  // The neighbourhood of the DEM square: positions and their index in the cloud.
  std::vector<Eigen::Vector3d> region;
  std::vector<int> region_index;
  std::vector<uint8_t> blunder;            // per cloud point
  std::vector<uint8_t> floating, on_face;  // per cloud point (objects along the lines of sight)
  // Region points that are no blunder and no sight-line object, and those objects.
  std::vector<Eigen::Vector3d> kept, seen_objects;
  std::vector<int> kept_index;
  std::vector<uint8_t> ground_of_kept;                   // ground filter's verdict per kept point
  KrigingPoints ground;                                  // the ground points, in the DEM's frame
  std::vector<int> ground_index;                         // their index in the cloud
  Eigen::Vector2d station_xy = Eigen::Vector2d::Zero();  // the mark, in the DEM's frame
  Eigen::Vector3d mark_dem = Eigen::Vector3d::Zero();
  KrigingResult kriged;
  SightLineCeilings ceilings;  // the lowest lines of sight over the DEM (products/dem_ceiling.tif)
  Raster horizon;  // over the cells the DEM leaves without a value (HorizonLimitResult::horizon)
  double coverage_30m = 0.0, coverage_square = 0.0;
  TerrainCorrection terrain_correction;
  nlohmann::json rig_check;  // report.json's "rig": the stage checked on the seams
  cv::Mat seams_image;       // products/seams.png, when the rig was checked
  // The sigma of the angle by which the rig's self-calibration may tilt every line of sight
  // (deg; 0: the calibration's stage taken as exact): the levelling, the tilt axis's zero and
  // the rig's pitch on its plate. Ground r metres out moves r times it, up or down.
  double sight_tilt_sigma_deg = 0.0;
};

bool FilterHeightBlunders(const ProcessOptions& o, StationWork* w, StepSummary* s);
bool FindObjectsAlongSightLines(const ProcessOptions& o, StationWork* w, StepSummary* s);
bool FilterGroundPoints(const ProcessOptions& o, StationWork* w, StepSummary* s);
bool RemoveUndersidePatches(const ProcessOptions& o, StationWork* w, StepSummary* s);
// Points whose line of sight went through the ground other points saw are blunders
// (free_space.h's FindLinesThroughSeenGround): out of the ground, and their lines not drawn.
bool RemovePointsSeenThroughGround(const ProcessOptions& o, StationWork* w, StepSummary* s);
bool KrigeStationDem(const ProcessOptions& o, StationWork* w, StepSummary* s);
bool LimitDemToHorizon(const ProcessOptions& o, StationWork* w, StepSummary* s);
// No DEM surface above a line of sight over it (free_space.h): every seen point's line.
bool KeepBelowSightLines(const ProcessOptions& o, StationWork* w, StepSummary* s);
// The std widened by what the ground could do where kriging cannot know (ground_room.h).
bool AddGroundRoom(const ProcessOptions& o, StationWork* w, StepSummary* s);
// The self-calibrated stage's sigmas tilt every line of sight (StationWork::sight_tilt_sigma_deg):
// sigma r at distance r from the station enters each cell's std.
bool AddSightTiltSigma(const ProcessOptions& o, StationWork* w, StepSummary* s);
bool CorrectTerrain(const ProcessOptions& o, StationWork* w, StepSummary* s);

}  // namespace ts
