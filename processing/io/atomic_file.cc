#include "processing/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ts {
namespace {

std::string ErrnoText(const std::string& path, const char* what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

bool WriteAll(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<size_t>(n));
  }
  return true;
}

Status FsyncDirectory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return Error{ErrnoText(dir.string(), "cannot open folder")};
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) return Error{ErrnoText(dir.string(), "cannot fsync folder")};
  return {};
}

// tmp, complete and fsync'd, renamed over path; the folder fsync'd. tmp removed on failure.
Status RenameIntoPlace(const std::string& tmp, const std::string& path) {
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string err = ErrnoText(path, "cannot rename into place");
    ::unlink(tmp.c_str());
    return Error{err};
  }
  return FsyncDirectory(std::filesystem::path(path).parent_path());
}

// fsync and close fd (open on tmp); tmp removed on failure.
Status SyncAndClose(int fd, bool written, const std::string& tmp, const std::string& path) {
  const bool synced = written && ::fsync(fd) == 0;
  if (::close(fd) != 0 || !synced) {
    const std::string err = ErrnoText(path, "cannot write");
    ::unlink(tmp.c_str());
    return Error{err};
  }
  return {};
}

}  // namespace

bool IsTemporaryName(const std::string& file_name) {
  return file_name.find(".tmp-") != std::string::npos;
}

std::string TemporaryPathFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
}

Status PublishAtomically(const std::string& tmp, const std::string& path) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const std::string err = ErrnoText(path, "cannot write");
    ::unlink(tmp.c_str());
    return Error{err};
  }
  if (Status s = SyncAndClose(fd, true, tmp, path); !s) return s;
  return RenameIntoPlace(tmp, path);
}

Status WriteFileAtomically(const std::string& path, std::string_view bytes) {
  const std::string tmp = TemporaryPathFor(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return Error{ErrnoText(path, "cannot create")};
  if (Status s = SyncAndClose(fd, WriteAll(fd, bytes), tmp, path); !s) return s;
  return RenameIntoPlace(tmp, path);
}

Result<std::string> ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot read file"};
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Error{path + ": read error"};
  return buffer.str();
}

}  // namespace ts
