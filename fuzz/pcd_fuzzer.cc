// A .pcd cloud: any bytes give points or one error, never a crash or an allocation the
// header did not earn.
#include "fuzz/fuzz_input.h"
#include "processing/io/point_cloud_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)ts::ReadPointCloudXyz(ts::fuzz::InputFile(data, size, "pcd"));
  return 0;
}
