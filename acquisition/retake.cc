#include "acquisition/retake.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "processing/common/angles.h"
#include "processing/io/station_manifest.h"

namespace ts {

namespace fs = std::filesystem;

Result<RetakeSummary> SetPairsAsideForRetake(const std::string& dir,
                                             const std::vector<StagePose>& poses,
                                             double tolerance_deg) {
  Result<StationManifest> m = LoadStationManifest(dir);
  if (!m) return Error{m.error()};
  RetakeSummary summary;
  std::string stamp = UtcNowIso8601();
  std::replace(stamp.begin(), stamp.end(), ':', '-');  // a folder name on any file system
  summary.folder = "retaken/" + stamp;
  std::vector<int> indices;
  for (const StagePose& pose : poses) {
    auto planned = std::find_if(m->plan.begin(), m->plan.end(), [&](const StagePose& p) {
      return AngleBetweenDeg(p.pan_deg, pose.pan_deg) <= tolerance_deg &&
             std::abs(p.tilt_deg - pose.tilt_deg) <= tolerance_deg;
    });
    if (planned == m->plan.end()) {
      m->plan.push_back(pose);
      ++summary.added;
    } else {
      indices.push_back(static_cast<int>(planned - m->plan.begin()));
    }
  }
  std::vector<PairRecord> kept;
  for (const PairRecord& p : m->pairs) {
    if (std::find(indices.begin(), indices.end(), p.index) == indices.end()) {
      kept.push_back(p);
      continue;
    }
    const fs::path aside = fs::path(dir) / summary.folder;
    std::error_code ec;
    fs::create_directories(aside, ec);
    for (const ImageRecord* image : {&p.left, &p.right}) {
      fs::rename(fs::path(dir) / image->file, aside / fs::path(image->file).filename(), ec);
      if (ec && fs::exists(fs::path(dir) / image->file))
        return Error{dir + "/" + image->file + ": cannot move it to " + summary.folder + ": " +
                     ec.message()};
    }
    ++summary.set_aside;
  }
  m->pairs = kept;
  if (Status s = SaveStationManifest(&*m, dir); !s) return Error{s.error()};
  return summary;
}

}  // namespace ts
