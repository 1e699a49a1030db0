// topostation: the command line of the appliance (DESIGN.md "Command line").
// Exit code 0 on success; otherwise one clear line on stderr and a non-zero code.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "core/log.h"
#include "processing/common/memory.h"
#include "station/commands.h"
#include "station/private_network.h"

int main(int argc, char** argv) {
  ts::RetainFreedMemory();  // large image buffers are reused, not returned per pair
  CLI::App app{"topostation: stereo-panorama DEMs and terrain correction for gravity stations"};
  app.require_subcommand(1);
  app.fallthrough();  // -v and -q also after the subcommand's name
  app.add_flag_function(
         "-v,--verbose",
         [](int64_t count) {
           ts::SetLogLevel(count > 1 ? ts::LogLevel::kDebug : ts::LogLevel::kInfo);
         },
         "log retries, resends and retakes (-vv: every step's counts too)")
      ->trigger_on_parse();
  app.add_flag_function(
         "-q,--quiet", [](int64_t) { ts::SetLogLevel(ts::LogLevel::kError); },
         "log errors only (no warnings)")
      ->trigger_on_parse();
  ts::AddAccuracyCommand(app);
  ts::AddValidateCommand(app);
  ts::AddSimCommand(app);
  ts::AddCaptureCommand(app);
  ts::AddDevicesCommand(app);
  ts::AddProcessCommands(app);
  ts::AddSurveyCommand(app);
  ts::AddTerrainCorrectionCommand(app);
  ts::AddDiffCommand(app);
  ts::AddCampaignCommand(app);
  ts::AddCalibrateCommand(app);
  ts::SetProgramArguments(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RequiredError& e) {
    // CLI11 says "A subcommand is required" also when a word was given that is none.
    int word = 1;
    while (word < argc && argv[word][0] == '-') ++word;  // -v, -q
    if (word < argc && app.get_subcommands().empty()) {
      std::string known;
      for (const CLI::App* sub : app.get_subcommands({}))
        known += (known.empty() ? "" : ", ") + sub->get_name();
      std::fprintf(stderr, "topostation: no command '%s' (commands: %s)\n", argv[word],
                   known.c_str());
      return 1;
    }
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ts::CommandError& e) {
    std::fprintf(stderr, "topostation: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "topostation: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
