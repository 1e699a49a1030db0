#pragma once
// Benchmarks print a table and write the same rows as JSON (--json FILE). Targets are
// checked here, never in unit tests; a row that misses its target makes the run fail.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace ts::bench {

struct Row {
  std::string name;
  double value = 0.0;
  std::string unit;
  std::string target;  // e.g. "<= 2.5", empty if informational
  bool met = true;
};

class Table {
 public:
  explicit Table(std::string title) : title_(std::move(title)) {}
  void Add(Row row) { rows_.push_back(std::move(row)); }
  // Prints the table, writes JSON if asked; returns the exit code (1 if a target was missed).
  int Finish(int argc, char** argv) const {
    std::printf("%s (%u cores)\n", title_.c_str(), std::thread::hardware_concurrency());
    std::printf("%-44s %14s %-8s %-12s %s\n", "measure", "value", "unit", "target", "met");
    bool all = true;
    nlohmann::json rows = nlohmann::json::array();
    for (const Row& r : rows_) {
      std::printf("%-44s %14.4g %-8s %-12s %s\n", r.name.c_str(), r.value, r.unit.c_str(),
                  r.target.c_str(), r.target.empty() ? "" : (r.met ? "yes" : "NO"));
      all = all && r.met;
      rows.push_back({{"name", r.name},
                      {"value", r.value},
                      {"unit", r.unit},
                      {"target", r.target},
                      {"met", r.met}});
    }
    for (int i = 1; i + 1 < argc; ++i) {
      if (std::string(argv[i]) == "--json") {
        std::ofstream(argv[i + 1]) << nlohmann::json{{"benchmark", title_},
                                                     {"cores", std::thread::hardware_concurrency()},
                                                     {"rows", rows}}
                                          .dump(2)
                                   << "\n";
      }
    }
    return all ? 0 : 1;
  }

 private:
  std::string title_;
  std::vector<Row> rows_;
};

// The seeds of `--seeds 2,3,...` (empty when not given).
inline std::vector<uint64_t> SeedsArgument(int argc, char** argv) {
  std::vector<uint64_t> seeds;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) != "--seeds") continue;
    std::stringstream list(argv[i + 1]);
    for (std::string item; std::getline(list, item, ',');) seeds.push_back(std::stoull(item));
  }
  return seeds;
}

// --only A,B,...: whether `name` is among the sets (or scenes) to run; all without the flag.
inline bool Wanted(int argc, char** argv, const std::string& name) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) != "--only") continue;
    std::stringstream list(argv[i + 1]);
    for (std::string item; std::getline(list, item, ',');)
      if (item == name) return true;
    return false;
  }
  return true;
}

// Wall time of fn in seconds: best of `repeats`.
template <typename Fn>
double BestSeconds(int repeats, Fn&& fn) {
  double best = 1e300;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

}  // namespace ts::bench
