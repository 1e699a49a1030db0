#include "station/private_network.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "station/commands.h"

namespace ts {
namespace {

std::vector<std::string>& ProgramArguments() {
  static std::vector<std::string> args;
  return args;
}

}  // namespace

void SetProgramArguments(int argc, char** argv) { ProgramArguments().assign(argv, argv + argc); }

bool HasSecondLoopbackAddress() {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return false;
  bool found = false;
  for (ifaddrs* a = list; a && !found; a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET) continue;
    const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
    found = ntohl(in->sin_addr.s_addr) == 0x7f000002;  // 127.0.0.2
  }
  freeifaddrs(list);
  return found;
}

std::string ThisProgram() {
  char exe[4096];
  const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) throw CommandError("cannot find this program (/proc/self/exe) to run it again");
  return std::string(exe, static_cast<size_t>(n));
}

void EnsurePrivateStationNetwork() {
  if (HasSecondLoopbackAddress()) return;
  if (const char* in = std::getenv("TS_IN_NETNS"); in && std::strcmp(in, "1") == 0)
    throw CommandError("private network namespace made, but 127.0.0.2 could not be added to lo");
  const std::string exe = ThisProgram();
  const std::vector<std::string>& own = ProgramArguments();
  if (own.empty()) throw CommandError("internal: program arguments were not saved");
  std::vector<std::string> args = {
      "unshare",
      ::geteuid() == 0 ? "-n" : "-rn",
      "env",
      "TS_IN_NETNS=1",
      "sh",
      "-c",
      "ip link set lo up && for a in 2 11 12; do ip addr add 127.0.0.$a/8 dev lo; done && "
      "exec \"$@\"",
      "topostation-netns",
      exe};
  args.insert(args.end(), own.begin() + 1, own.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execvp("unshare", argv.data());
  throw CommandError(std::string("cannot start a private network namespace (unshare: ") +
                     std::strerror(errno) + "); install util-linux and iproute2");
}

}  // namespace ts
