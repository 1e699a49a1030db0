// RIG.yaml: any bytes give a rig config or one error, never a crash.
#include "acquisition/rig_config.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)ts::LoadRigConfig(ts::fuzz::InputFile(data, size, "yaml"));
  return 0;
}
