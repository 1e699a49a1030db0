#pragma once
// The simulated station needs 127.0.0.2 on lo (DESIGN.md "Simulator"). A command that serves
// it (survey --sim) arranges that itself: it re-executes itself in a network namespace of its
// own with lo up and 127.0.0.2 (and .11, .12 for the gvsp-loss relay) on it, inside a user
// namespace when not root, exactly as scripts/netns-run does for tests. Nothing outside the
// namespace changes; files written land in the same file system.
#include <string>
#include <vector>

namespace ts {

// The program's own arguments, saved by main() for a re-execution.
void SetProgramArguments(int argc, char** argv);

// This program's executable (/proc/self/exe), to run it again; throws CommandError if unknown.
std::string ThisProgram();

// True when 127.0.0.2 is an address of this network namespace.
bool HasSecondLoopbackAddress();

// Returns when 127.0.0.2 is already here; otherwise re-executes the program with the same
// arguments in a private network namespace and never returns (throws CommandError if that
// cannot be done).
void EnsurePrivateStationNetwork();

}  // namespace ts
