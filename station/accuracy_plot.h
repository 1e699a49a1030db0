#pragma once
// PNG plot of the theoretical accuracy table (sigma X, Y, Z against range), as seed 003 fig. 2.
#include <string>
#include <vector>

#include "core/result.h"
#include "processing/geometry/theoretical_accuracy.h"

namespace ts {

Status WriteAccuracyPlot(const std::vector<AccuracyRow>& rows, const std::string& title,
                         const std::string& png_path);

}  // namespace ts
