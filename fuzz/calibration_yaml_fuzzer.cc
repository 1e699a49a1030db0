// calibration.yaml: any bytes give a calibration or one error, never a crash.
#include "fuzz/fuzz_input.h"
#include "processing/io/calibration_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)ts::LoadCalibrationYaml(ts::fuzz::InputFile(data, size, "yaml"));
  return 0;
}
