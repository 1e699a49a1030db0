// A raw image of a station (64 x 48 Mono8 declared): any bytes give the image or one error.
#include "fuzz/fuzz_input.h"
#include "processing/io/image_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)ts::ReadMonoPng(ts::fuzz::InputFile(data, size, "png"), ts::PixelFormat::kMono8, 64, 48);
  return 0;
}
