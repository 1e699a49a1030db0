// topostation campaign DIR... --out campaign.csv [--gpkg FILE]: every station of a survey in
// one table (station/campaign.h), and the GeoPackage beside it (default: the table's name
// with .gpkg).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "processing/io/atomic_file.h"
#include "station/campaign.h"
#include "station/commands.h"

namespace ts {
namespace {

struct CampaignArgs {
  std::vector<std::string> dirs;
  std::string out, gpkg;
};

void RunCampaign(const CampaignArgs& args) {
  const Result<std::vector<std::string>> stations = FindStations(args.dirs);
  if (!stations) throw CommandError(stations.error());
  std::vector<nlohmann::ordered_json> rows;
  for (const std::string& dir : *stations) {
    Result<nlohmann::ordered_json> row = CampaignRow(dir);
    if (!row) throw CommandError(row.error());
    rows.push_back(*std::move(row));
  }
  if (Status s = WriteFileAtomically(args.out, CampaignCsv(rows)); !s)
    throw CommandError(s.error());
  const std::string gpkg = args.gpkg.empty()
                               ? std::filesystem::path(args.out).replace_extension(".gpkg").string()
                               : args.gpkg;
  if (Status s = WriteCampaignGeoPackage(rows, *stations, gpkg); !s) throw CommandError(s.error());
  std::printf("%zu stations: %s and %s\n", rows.size(), args.out.c_str(), gpkg.c_str());
}

}  // namespace

void AddCampaignCommand(CLI::App& app) {
  auto args = std::make_shared<CampaignArgs>();
  CLI::App* c = app.add_subcommand(
      "campaign", "Every station of a survey in one table (CSV) and a GeoPackage for QGIS");
  c->add_option("dirs", args->dirs, "station directories, or directories of stations")->required();
  c->add_option("--out", args->out, "the table (CSV)")->required();
  c->add_option("--gpkg", args->gpkg, "the GeoPackage (default: the table's name, .gpkg)");
  c->callback([args] { RunCampaign(*args); });
}

}  // namespace ts
