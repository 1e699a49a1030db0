// The campaign's reprocessing workflow (workflow/Snakefile) run by Debian's snakemake on two
// simulated stations (one rig, two epochs of a site), captured with the rig's design values
// and reprocessed with its calibration at a new density: every station processed with both,
// the table's rows equal to each station's own report, the GeoPackage opened with GDAL.
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "processing/io/json_fields.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

namespace fs = std::filesystem;

int ExitStatusOf(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::map<std::string, std::string>> ReadCsv(const std::string& file) {
  std::ifstream in(file);
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {  // the columns compared below hold no escaped quotes
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        cells.push_back(cell), cell.clear();
      else
        cell += c;
    }
    cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

TEST(CampaignWorkflow, SnakemakeReprocessesTwoStationsWithANewCalibrationAndDensity) {
  testing::TempDir temp;
  const fs::path dir = temp.path();
  const std::vector<std::string> ids = {"W1", "W2"};
  for (size_t i = 0; i < ids.size(); ++i) {
    const std::string station = (dir / "stations" / ids[i]).string();
    ASSERT_EQ(ExitStatusOf(std::string(TS_TOPOSTATION_EXE) +
                           " sim render --scene hills --seed 1 --single-row --supersampling 1" +
                           " --epoch " + std::to_string(i + 1) + " --out " + station + " --truth " +
                           station + "-truth > /dev/null"),
              0);
  }
  const std::string out = (dir / "out").string();
  const std::string calibration = (dir / "stations/W1-truth/calibration.yaml").string();
  const std::string log = (dir / "snakemake.log").string();
  const int rc =
      ExitStatusOf("snakemake -s " TS_SOURCE_DIR "/workflow/Snakefile --cores 2 --directory " +
                   (dir / "work").string() + " --config stations=" + (dir / "stations").string() +
                   " out=" + out + " density=2.2 calibration=" + calibration +
                   " topostation=" + TS_TOPOSTATION_EXE + " > " + log + " 2>&1");
  std::ifstream snake_log(log);
  ASSERT_EQ(rc, 0) << std::string((std::istreambuf_iterator<char>(snake_log)), {});

  const auto rows = ReadCsv(out + "/campaign.csv");
  ASSERT_EQ(rows.size(), ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    const fs::path station = dir / "stations" / ids[i];
    const nlohmann::json report = ReadJsonFileOrNull((station / "products/report.json").string());
    const nlohmann::json tc = ReadJsonFileOrNull(out + "/" + ids[i] + "/terrain_correction.json");
    ASSERT_TRUE(report.is_object() && tc.is_object()) << ids[i];
    const nlohmann::json manifest = ReadJsonFileOrNull((station / "station.json").string());
    EXPECT_EQ(rows[i].at("station"), manifest["station_id"]);
    ASSERT_TRUE(report["terrain_correction_mgal"].is_number()) << report.dump();
    EXPECT_NE(rows[i].at("calibration").find(calibration), std::string::npos)
        << rows[i].at("calibration");
    EXPECT_EQ(tc["density_g_cm3"], 2.2);
    EXPECT_EQ(report["options"]["terrain_correction"]["density_kg_m3"], 2200.0);
    EXPECT_DOUBLE_EQ(std::stod(rows[i].at("density_g_cm3")), 2.2);
    EXPECT_DOUBLE_EQ(std::stod(rows[i].at("terrain_correction_mgal")),
                     report["terrain_correction_mgal"].get<double>());
    EXPECT_DOUBLE_EQ(std::stod(rows[i].at("terrain_correction_sigma_mgal")),
                     report["terrain_correction_sigma_mgal"].get<double>());
    EXPECT_DOUBLE_EQ(std::stod(rows[i].at("coverage_30m")),
                     report["dem"]["coverage_30m"].get<double>());
  }
  GDALAllRegister();
  const std::string gpkg = out + "/campaign.gpkg";
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(gpkg.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  ASSERT_TRUE(ds);
  OGRLayer* points = ds->GetLayerByName("stations");
  ASSERT_TRUE(points);
  EXPECT_EQ(points->GetFeatureCount(), static_cast<GIntBig>(ids.size()));

  // Run again: nothing to do, every output is newer than its inputs.
  EXPECT_EQ(
      ExitStatusOf("snakemake -s " TS_SOURCE_DIR "/workflow/Snakefile --cores 2 --directory " +
                   (dir / "work").string() + " --config stations=" + (dir / "stations").string() +
                   " out=" + out + " density=2.2 calibration=" + calibration +
                   " topostation=" + TS_TOPOSTATION_EXE + " -n > " + log + " 2>&1"),
      0);
  std::ifstream again(log);
  const std::string text((std::istreambuf_iterator<char>(again)), {});
  EXPECT_NE(text.find("Nothing to be done"), std::string::npos) << text;
}

}  // namespace
}  // namespace ts
