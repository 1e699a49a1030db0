// Bad input, as a property (issue 23): valid stations, calibrations, rasters and clouds,
// mutated at random (seeded) in the ways files go wrong — a number set to what no rig or site
// has, a field dropped, a byte flipped, the file cut short — and run through the commands.
// Whatever the mutation: no signal, no timeout, no "internal error", exit 0 or 1, never a nan
// or inf in what is printed, and an exit-0 terrain correction that is a finite number with a
// finite sigma (or says it is unusable).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>

#include "processing/io/point_cloud_file.h"
#include "processing/io/raster.h"
#include "tests/common/station_fixture.h"
#include "tests/common/temp_dir.h"

namespace ts {
namespace {

using nlohmann::json;
using testing::RunCommand;

// Values a field goes wrong with.
const std::vector<json> kBadValues = {
    0, -1, 1e308, -1e308, 1e-300, 4294967296.0, "x", nullptr, json::array(), json::object(), true};

std::string Text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void Write(const std::string& file, const std::string& text) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
}

// Every leaf of a JSON document, as a pointer.
void Leaves(const json& j, const json::json_pointer& at, std::vector<json::json_pointer>* out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) Leaves(*it, at / it.key(), out);
  } else if (j.is_array() && !j.empty()) {
    for (size_t i = 0; i < j.size(); ++i) Leaves(j[i], at / i, out);
  } else {
    out->push_back(at);
  }
}

// One mutation of a JSON document: a leaf set to a bad value, or removed.
std::string MutateJson(const std::string& text, std::mt19937* rng) {
  json doc = json::parse(text);
  std::vector<json::json_pointer> leaves;
  Leaves(doc, json::json_pointer(), &leaves);
  const json::json_pointer& leaf = leaves[(*rng)() % leaves.size()];
  if ((*rng)() % 5 == 0 && !leaf.empty()) {
    doc[leaf.parent_pointer()].is_object()
        ? static_cast<void>(doc[leaf.parent_pointer()].erase(leaf.back()))
        : static_cast<void>(doc[leaf] = nullptr);
  } else {
    doc[leaf] = kBadValues[(*rng)() % kBadValues.size()];
  }
  return doc.dump(2);
}

// One mutation of any file: bytes flipped, or the file cut short.
std::string MutateBytes(std::string bytes, std::mt19937* rng) {
  if (bytes.empty()) return bytes;
  if ((*rng)() % 4 == 0) return bytes.substr(0, (*rng)() % bytes.size());
  const int flips = 1 + static_cast<int>((*rng)() % 8);
  // Mostly in the header, where the declared sizes are.
  const size_t span = std::min<size_t>(bytes.size(), (*rng)() % 2 ? 400 : bytes.size());
  for (int k = 0; k < flips; ++k) bytes[(*rng)() % span] ^= static_cast<char>(1 + (*rng)() % 255);
  return bytes;
}

// What every run must hold to.
void ExpectHonest(const testing::CommandOutput& r, const std::string& what) {
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << what << ": exit " << r.exit_code << "\n"
                                                    << r.out;
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << what << "\n" << r.out;
  static const std::regex kNotANumber(R"((^|[^a-z])(nan|inf)([^a-z]|$))", std::regex::icase);
  EXPECT_FALSE(std::regex_search(r.out, kNotANumber)) << what << "\n" << r.out;
}

std::string Exe() { return std::string("timeout 60 ") + TS_TOPOSTATION_EXE; }

TEST(BadInputProperty, MutatedManifestsAreValidatedOrRefusedWithOneError) {
  testing::TempDir dir;
  const std::string station = dir / "S";
  testing::MakeStation(station, 3, 3);
  const std::string good = Text(station + "/station.json");
  std::mt19937 rng(23);
  for (int k = 0; k < 60; ++k) {
    Write(station + "/station.json", MutateJson(good, &rng));
    const auto r = RunCommand(Exe() + " validate " + station + " 2>&1");
    ExpectHonest(r, "validate, mutation " + std::to_string(k));
    if (r.exit_code == 1) {
      EXPECT_NE(r.out.find("station.json"), std::string::npos) << r.out;
    }
  }
}

TEST(BadInputProperty, MutatedCalibrationsAreUsedOrRefusedWithOneError) {
  testing::TempDir dir;
  const std::string station = dir / "S";
  const StationManifest m = testing::MakeStation(station, 2, 2);
  // The manifest's calibration as a file of its own, in YAML's JSON subset.
  const std::string good = json::parse(Text(station + "/station.json"))["calibration"].dump();
  std::mt19937 rng(21);
  for (int k = 0; k < 40; ++k) {
    Write(dir / "cal.yaml", MutateJson(good, &rng));
    const auto r = RunCommand(Exe() + " process " + station + " --calibration " +
                              (dir / "cal.yaml") + " -q 2>&1");
    ExpectHonest(r, "process --calibration, mutation " + std::to_string(k));
  }
}

TEST(BadInputProperty, MutatedCloudsAreFilteredOrRefusedWithOneError) {
  testing::TempDir dir;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 400; ++i) points.emplace_back(0.5 * (i % 20), 0.5 * (i / 20), 0.01 * (i % 7));
  ASSERT_TRUE(WritePly(dir / "good.ply", points));
  const std::string good = Text(dir / "good.ply");
  std::mt19937 rng(22);
  for (int k = 0; k < 60; ++k) {
    Write(dir / "cloud.ply", MutateBytes(good, &rng));
    const auto r = RunCommand(Exe() + " ground-filter " + (dir / "cloud.ply") + " --out " +
                              (dir / "g.ply") + " 2>&1");
    ExpectHonest(r, "ground-filter, mutation " + std::to_string(k));
  }
}

TEST(BadInputProperty, MutatedDemsGiveAFiniteCorrectionOrOneError) {
  testing::TempDir dir;
  Raster dem = Raster::Make(-30, 30, 1.0, 60, 60);
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 60; ++c)
      dem.at(r, c) = static_cast<float>(0.1 * dem.CellCentreX(c) + 0.3 * std::sin(r / 5.0));
  ASSERT_TRUE(WriteGeoTiff(dem, dir / "good.tif"));
  const std::string good = Text(dir / "good.tif");
  std::mt19937 rng(24);
  const std::vector<std::string> cells = {"0", "1e30", "-1e30", "3e38", "nan"};
  for (int k = 0; k < 60; ++k) {
    if (k % 2 == 0) {
      Write(dir / "dem.tif", MutateBytes(good, &rng));
    } else {  // a readable DEM with values no ground has
      Raster bad = dem;
      for (int n = 0; n < 1 + static_cast<int>(rng() % 50); ++n)
        bad.values[rng() % bad.values.size()] = std::stof(cells[rng() % cells.size()]);
      ASSERT_TRUE(WriteGeoTiff(bad, dir / "dem.tif"));
    }
    const auto r = RunCommand(Exe() + " terrain-correction " + (dir / "dem.tif") +
                              " --station 0,0 --json --out " + (dir / "tc.json") + " 2>&1");
    ExpectHonest(r, "terrain-correction, mutation " + std::to_string(k));
    if (r.exit_code != 0) continue;
    const json j = json::parse(r.out, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r.out;
    if (j["verdict"] == "unusable") continue;
    EXPECT_TRUE(j["terrain_correction_mgal"].is_number()) << r.out;
    EXPECT_TRUE(j["sigma_mgal"].is_number()) << r.out;
    // Plausible: a 60 m square of real ground gives far less than a few mGal.
    EXPECT_LT(std::abs(j["terrain_correction_mgal"].get<double>()), 10.0) << k;
  }
}

}  // namespace
}  // namespace ts
