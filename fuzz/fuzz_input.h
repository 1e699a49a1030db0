#pragma once
// The loaders read files: each input is written to one file per fuzzer process, with the
// extension the loader dispatches on.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

namespace ts::fuzz {

inline std::string InputFile(const uint8_t* data, size_t size, const std::string& extension) {
  const std::string path = "/tmp/topostation-fuzz-" + std::to_string(getpid()) + "." + extension;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace ts::fuzz
