// station.json: any bytes give a manifest or one error, never a crash.
#include <string>

#include "processing/io/station_manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)ts::ManifestFromJson(std::string(reinterpret_cast<const char*>(data), size),
                             "fuzz/station.json");
  return 0;
}
