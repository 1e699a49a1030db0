#pragma once
// The report a calibration leaves beside its file (DIR = the file's name without extension,
// then ".report"): report.json (what `--json` prints) and pictures a user reads at a glance:
//   residuals_NAME.png   each observation's residual vector over the frame, magnified
//   histogram_NAME.png   the residuals' components against the normal curve of sigma0
//   view_rms_NAME.png    the RMS of each view (a bad view stands out)
//   coverage_NAME.png    the observations per cell of the frame
//   uncertainty.png      the validated map's sigma over the frame, per distance
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"
#include "processing/calibration/calibration_validation.h"
#include "processing/calibration/camera_calibration.h"

namespace ts {

struct CalibrationReport {
  nlohmann::json summary;
  std::vector<std::pair<std::string, const CameraCalibration*>> cameras;  // "left", ...
  const CalibrationValidation* validation = nullptr;
};

std::string CalibrationReportDir(const std::string& calibration_file);

// Returns the files written.
Result<std::vector<std::string>> WriteCalibrationReport(const CalibrationReport& report,
                                                        const std::string& dir);

}  // namespace ts
