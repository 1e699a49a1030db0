#pragma once
// Pixel formats of the rig's cameras and of a station's raw images (GenICam names).
#include <string>

#include "core/result.h"

namespace ts {

enum class PixelFormat { kMono8, kMono16 };
const char* PixelFormatName(PixelFormat format);  // "Mono8" / "Mono16"
Result<PixelFormat> PixelFormatFromName(const std::string& name);

}  // namespace ts
