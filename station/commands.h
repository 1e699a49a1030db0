#pragma once
// Each `topostation` subcommand registers itself on the CLI11 app. A command reports failure
// by throwing CommandError with one clear line; main() prints it and exits non-zero.
#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "acquisition/capture.h"
#include "acquisition/rig_config.h"
#include "processing/pipeline/process_station.h"

namespace ts {

class CommandError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void AddAccuracyCommand(CLI::App& app);
void AddValidateCommand(CLI::App& app);
void AddSimCommand(CLI::App& app);
void AddCaptureCommand(CLI::App& app);
void AddDevicesCommand(CLI::App& app);
void AddProcessCommands(CLI::App& app);  // process, evaluate, ground-filter
void AddSurveyCommand(CLI::App& app);
void AddTerrainCorrectionCommand(CLI::App& app);
void AddDiffCommand(CLI::App& app);
void AddCampaignCommand(CLI::App& app);
void AddCalibrateCommand(CLI::App& app);
void AddCalibrateRigCommand(CLI::App* calibrate);  // under `calibrate`

// Shared by the commands that chain them (survey): each throws CommandError on failure.
// observer (optional) sees every capture event, e.g. to hand each committed pair to an
// incremental station.
CaptureSummary CaptureOrThrow(const RigConfig& rig, const std::string& station_dir, bool resume,
                              const CaptureOptions& options, bool show_progress,
                              const std::function<void(const CaptureEvent&)>& observer = {});
nlohmann::json ProcessOrThrow(const std::string& station_dir, const ProcessOptions& options,
                              bool show_progress);
// The products of a station whose pairs went to `processor` as they were committed.
nlohmann::json FinishOrThrow(StationProcessor* processor);

// The terrain correction (or why it is unusable) and the DEM's counts of a report.json.
void PrintProcessSummary(const std::string& station_dir, const nlohmann::json& report);

// products/evaluation.json of a processed station against a truth directory.
nlohmann::json EvaluateOrThrow(const std::string& station_dir, const std::string& truth_dir);
// Its two summary lines (DEM errors and coverage; terrain correction against the truth's).
void PrintEvaluation(const nlohmann::json& evaluation);

}  // namespace ts
