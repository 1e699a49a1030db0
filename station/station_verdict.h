#pragma once
// Is this station good enough to pack up? The operator's question before leaving a gravity
// station (issue 25), answered in plain words from the terrain correction and its ring and
// sector table, against the sigma the crew asked for:
//   good       sigma within what was asked;
//   retake     sigma beyond it, and ground a view reaches but the cameras did not see (a
//              passer-by, a vehicle, a dark pair) holds enough of it that taking the poses
//              looking there again would lower sigma by a tenth or more: those poses;
//   as good as it gets  sigma beyond it, and no retake would lower it by a tenth: most of it
//              seen already (the terrain's own roughness), nearer than any view reaches
//              (under the rig: measured by hand), or spread over many directions;
//   unusable   the correction has no value (too little ground seen): the poses facing the
//              emptiest direction.
// The direction is a bearing in the station frame L, where it equals the stage's pan.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/stage_pose.h"

namespace ts {

// When the crew did not say: the usual aim of a microgravity survey's terrain correction.
constexpr double kDefaultRequiredSigmaMgal = 0.01;

struct StationVerdict {
  std::string verdict;            // good | retake | as good as it gets | unusable | not processed
  std::string text;               // one sentence for the operator
  std::vector<StagePose> retake;  // poses of the plan to take again
  nlohmann::json ToJson() const;
};

// tc: terrain_correction.json (null: not processed); plan: the capture plan's poses;
// nearest_view_m: the ground range the lowest views' bottom edge reaches (nearer ground no
// pose sees).
StationVerdict JudgeStation(const nlohmann::json& tc, const std::vector<StagePose>& plan,
                            double required_sigma_mgal, double nearest_view_m = 0.0);

// The same from a station directory: station.json's plan and calibration,
// station_fields.json's
// required_sigma_mgal (else the default), products/terrain_correction.json.
StationVerdict JudgeStationDir(const std::string& station_dir);

}  // namespace ts
