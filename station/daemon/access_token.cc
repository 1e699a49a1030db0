#include "station/daemon/access_token.h"

#include <fcntl.h>
#include <openssl/crypto.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace ts::daemon {
namespace {

constexpr size_t kTokenBytes = 32;  // 256 bits

Result<std::string> NewToken() {
  unsigned char bytes[kTokenBytes];
  size_t got = 0;
  while (got < kTokenBytes) {
    const ssize_t n = ::getrandom(bytes + got, kTokenBytes - got, 0);
    if (n < 0) return Error{std::string("getrandom: ") + std::strerror(errno)};
    got += static_cast<size_t>(n);
  }
  std::string hex;
  char pair[3];
  for (unsigned char b : bytes) {
    std::snprintf(pair, sizeof(pair), "%02x", b);
    hex += pair;
  }
  return hex;
}

}  // namespace

Result<std::string> LoadOrCreateToken(const std::string& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) == 0) {
    if (st.st_mode & (S_IRWXG | S_IRWXO)) {
      char mode[8];
      std::snprintf(mode, sizeof(mode), "%04o", st.st_mode & 07777);
      return Error{file + ": mode " + mode + " lets others read the token (chmod 600 " + file +
                   ")"};
    }
    std::ifstream in(file);
    std::string token;
    std::getline(in, token);
    if (token.size() != 2 * kTokenBytes ||
        !std::all_of(token.begin(), token.end(), [](char c) { return std::isxdigit(c); }))
      return Error{file + ": not a token of 64 hex digits (delete it to make a new one)"};
    return token;
  }
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(file).parent_path(), ec);
  const Result<std::string> token = NewToken();
  if (!token) return token;
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) return Error{file + ": cannot create the token file: " + std::strerror(errno)};
  const std::string line = *token + "\n";
  const bool written = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  if (!written || !synced) return Error{file + ": cannot write the token file"};
  return token;
}

bool TokenMatches(const std::string& presented, const std::string& expected) {
  // Compare as many bytes as the expected token has, whatever was presented, so that the time
  // says nothing of how much of it was right.
  std::string padded = presented;
  padded.resize(expected.size(), '\0');
  return CRYPTO_memcmp(padded.data(), expected.data(), expected.size()) == 0 &&
         presented.size() == expected.size();
}

int AuthThrottle::WaitSeconds(const std::string& address, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  auto it = records_.find(address);
  if (it == records_.end() || it->second.blocked_until <= now) return 0;
  return static_cast<int>(
      std::chrono::ceil<std::chrono::seconds>(it->second.blocked_until - now).count());
}

void AuthThrottle::Failed(const std::string& address, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (records_.size() >= kMaxRecords)  // many addresses: forget those not blocked now
    std::erase_if(records_, [&](const auto& entry) { return entry.second.blocked_until <= now; });
  Record& r = records_[address];
  ++r.failures;
  if (r.failures < kFreeFailures) return;
  const int doublings = std::min(r.failures - kFreeFailures, 6);
  r.blocked_until = now + std::chrono::seconds(std::min(1 << doublings, 60));
}

void AuthThrottle::Succeeded(const std::string& address) {
  std::lock_guard lock(mutex_);
  records_.erase(address);
}

}  // namespace ts::daemon
