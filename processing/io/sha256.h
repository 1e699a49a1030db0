#pragma once
// SHA-256 (OpenSSL) as lower-case hex, for the checksums of the station manifest.
#include <string>
#include <string_view>

#include "core/result.h"

namespace ts {

std::string Sha256Hex(std::string_view bytes);
Result<std::string> Sha256OfFile(const std::string& path);

}  // namespace ts
