// topostation validate STATION: checks a station directory against its manifest.
#include <cstdio>
#include <memory>

#include "processing/io/station_validator.h"
#include "station/commands.h"

namespace ts {

void AddValidateCommand(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto complete = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "validate", "Check a station directory: manifest, every image, checksums and sizes");
  cmd->add_option("STATION", *dir, "station directory")->required();
  cmd->add_flag("--complete", *complete, "also require every pair of the capture plan");
  cmd->callback([dir, complete] {
    StationValidationOptions options;
    options.require_complete = *complete;
    const Result<StationManifest> m = ValidateStation(*dir, options);
    if (!m) throw CommandError(m.error());
    std::printf("%s: valid, %zu of %zu pairs\n", dir->c_str(), m->pairs.size(), m->plan.size());
  });
}

}  // namespace ts
