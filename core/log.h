#pragma once
// The program's one log (spdlog), for what an operator or a service's journal should see:
// Modbus retries, GVSP resends, retaken exposures, every warning of a job. On a terminal it
// writes "warning: ..." lines to stderr; under systemd (JOURNAL_STREAM set, stderr to the
// journal) each line starts with its syslog priority ("<4>...") so journalctl shows levels.
// Thread-safe: devices, the matching worker and the daemon's threads log alike.
#include <spdlog/spdlog.h>

namespace ts {

enum class LogLevel { kDebug, kInfo, kWarning, kError, kOff };

// Sets the level (default kWarning; --verbose kInfo or kDebug, --quiet kError).
void SetLogLevel(LogLevel level);
spdlog::logger& Log();

}  // namespace ts
