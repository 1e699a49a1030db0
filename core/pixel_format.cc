#include "core/pixel_format.h"

namespace ts {

const char* PixelFormatName(PixelFormat format) {
  return format == PixelFormat::kMono8 ? "Mono8" : "Mono16";
}

Result<PixelFormat> PixelFormatFromName(const std::string& name) {
  if (name == "Mono8") return PixelFormat::kMono8;
  if (name == "Mono16") return PixelFormat::kMono16;
  return Error{"unknown pixel format '" + name + "' (Mono8 or Mono16)"};
}

}  // namespace ts
