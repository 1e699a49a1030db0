// RetainFreedMemory: after it, a freed image-sized buffer stays in the process for the next
// allocation (by default glibc unmaps it and the next one is page-faulted again).
#include "processing/common/memory.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <cstdlib>
#include <cstring>

namespace ts {
namespace {

TEST(Memory, FreedImageBuffersStayInTheProcess) {
  ASSERT_TRUE(RetainFreedMemory());
  constexpr size_t kImage = 8u << 20;  // a 2-megapixel float image
  const size_t mapped_before = mallinfo2().hblkhd;
  void* image = std::malloc(kImage);
  ASSERT_NE(image, nullptr);
  std::memset(image, 1, kImage);
  EXPECT_EQ(mallinfo2().hblkhd, mapped_before);  // from the heap, not a mapping of its own
  std::free(image);
  EXPECT_GE(mallinfo2().fordblks, kImage);  // kept, free for the next image
}

}  // namespace
}  // namespace ts
