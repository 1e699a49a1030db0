#include "station/station_archive.h"

#include <cpl_conv.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "processing/io/atomic_file.h"
#include "processing/io/station_manifest.h"

namespace ts {
namespace {

namespace fs = std::filesystem;

struct ZipCloser {
  void operator()(void* zip) const { CPLCloseZip(zip); }
};

Status AddFile(void* zip, const fs::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return Error{file.string() + ": cannot read"};
  if (CPLCreateFileInZip(zip, name.c_str(), nullptr) != CE_None)
    return Error{name + ": cannot add to the zip"};
  std::vector<char> buffer(1 << 16);
  Status status;
  while (status && in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (in.gcount() > 0 &&
        CPLWriteFileInZip(zip, buffer.data(), static_cast<int>(in.gcount())) != CE_None)
      status = Error{name + ": cannot write into the zip"};
  }
  CPLCloseFileInZip(zip);
  return status;
}

}  // namespace

Status WriteStationArchive(const std::string& station_dir, const std::string& zip_file) {
  const fs::path dir(station_dir);
  const std::string station = dir.filename().string();
  std::vector<std::pair<fs::path, std::string>> files;
  for (const char* name : {kManifestFileName, "station_fields.json"})
    if (fs::is_regular_file(dir / name)) files.emplace_back(dir / name, station + "/" + name);
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir / "products", ec))
    if (e.is_regular_file())
      files.emplace_back(e.path(), station + "/products/" + e.path().filename().string());
  // Written aside and renamed into place: two downloads at once each write their own.
  const std::string partial = TemporaryPathFor(zip_file);
  Status written;
  {
    std::unique_ptr<void, ZipCloser> zip(CPLCreateZip(partial.c_str(), nullptr));
    if (!zip) return Error{zip_file + ": cannot create"};
    for (const auto& [file, name] : files)
      if (written) written = AddFile(zip.get(), file, name);
  }
  if (!written) {
    fs::remove(partial, ec);
    return written;
  }
  return PublishAtomically(partial, zip_file);
}

}  // namespace ts
