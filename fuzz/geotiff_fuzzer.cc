// A DEM GeoTIFF: any bytes give a raster or one error, never a crash.
#include "fuzz/fuzz_input.h"
#include "processing/io/raster.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)ts::ReadGeoTiff(ts::fuzz::InputFile(data, size, "tif"));
  return 0;
}
