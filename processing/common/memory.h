#pragma once
// Keeping freed memory in the process. Matching allocates and frees many large image buffers
// per pair; by default glibc gives each back to the kernel (mmap / munmap) and the next one is
// page-faulted and zeroed again. Measured on the 12 flat pairs, 2 cores: 15-20 % of the
// matching wall time. The appliance's peak memory is unchanged: freed memory is reused, not
// returned until the process ends. Call once, early in main.
namespace ts {

// True when glibc accepted the settings.
bool RetainFreedMemory();

}  // namespace ts
