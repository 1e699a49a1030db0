#pragma once
// Crash-safe file output: every file of a station directory is written to a temporary name
// in the same folder, fsync'd, renamed over the final name, and the folder fsync'd, so a
// power cut or kill -9 leaves either the old file or the complete new one, never a torn one.
#include <string>
#include <string_view>

#include "core/result.h"

namespace ts {

Status WriteFileAtomically(const std::string& path, std::string_view bytes);
// For libraries that write to a path themselves (PCL): let them write to TemporaryPathFor(path),
// then PublishAtomically makes it final (fsync, rename, folder fsync); tmp is removed on failure.
std::string TemporaryPathFor(const std::string& path);
Status PublishAtomically(const std::string& tmp, const std::string& path);
Result<std::string> ReadWholeFile(const std::string& path);
// Temporary names look like "<name>.tmp-<pid>-<n>"; a crashed writer may leave one behind.
bool IsTemporaryName(const std::string& file_name);

}  // namespace ts
