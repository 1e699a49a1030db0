#include "processing/common/memory.h"

#include <malloc.h>

namespace ts {

bool RetainFreedMemory() {
  // Blocks up to 32 MiB from the heap, not from their own mappings; up to 1 GiB of free memory
  // at the top of the heap is kept.
  constexpr int kMmapThreshold = 32 << 20;  // glibc's largest on 64-bit systems
  constexpr int kTrimThreshold = 1 << 30;
  return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 &&
         mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
}

}  // namespace ts
