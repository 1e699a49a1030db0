#pragma once
// The software's version as report.json records it: "0.1.0 (git 1a2b3c4d)", "-dirty" when
// built from a tree with uncommitted changes. Generated at every build (cmake/version.cmake).
#include <string>

namespace ts {

std::string SoftwareVersion();

}  // namespace ts
