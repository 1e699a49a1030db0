#pragma once
// Each `topostation` subcommand registers itself on the CLI11 app. A command reports failure
// by throwing CommandError with one clear line; main() prints it and exits non-zero.
#include <CLI/CLI.hpp>
#include <stdexcept>

namespace ts {

class CommandError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void AddAccuracyCommand(CLI::App& app);
void AddValidateCommand(CLI::App& app);
void AddSimCommand(CLI::App& app);
void AddCaptureCommand(CLI::App& app);
void AddDevicesCommand(CLI::App& app);

}  // namespace ts
