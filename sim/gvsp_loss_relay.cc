#include "sim/gvsp_loss_relay.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <deque>
#include <map>
#include <vector>

#include "sim/noise.h"

namespace ts::sim {
namespace {

// GigE Vision constants (GVCP: control; GVSP: stream), all fields big-endian.
constexpr uint16_t kGvcpPort = 3956;
constexpr uint16_t kPacketResendCmd = 0x0040;
constexpr uint16_t kWriteRegisterCmd = 0x0082;
constexpr uint32_t kStreamChannelPort = 0x0d00;     // SCP0: host port in the low 16 bits
constexpr uint32_t kStreamChannelAddress = 0x0d18;  // SCDA0: host IPv4 address
constexpr size_t kGvcpHeader = 8;
constexpr size_t kKeptFrames = 4;

uint16_t Get16(const uint8_t* p) { return static_cast<uint16_t>(p[0] << 8 | p[1]); }
uint32_t Get32(const uint8_t* p) {
  return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | p[3];
}
void Put32(uint8_t* p, uint32_t v) {
  p[0] = v >> 24, p[1] = v >> 16, p[2] = v >> 8, p[3] = v & 0xff;
}

int UdpSocket(uint32_t ip, uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(ip);
  a.sin_port = htons(port);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

sockaddr_in Address(uint32_t ip, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(ip);
  a.sin_port = htons(port);
  return a;
}

}  // namespace

Result<std::unique_ptr<GvspLossRelay>> GvspLossRelay::Start(const std::string& public_address,
                                                            const std::string& camera_address,
                                                            double loss_ratio, uint64_t seed) {
  in_addr pub{}, cam{};
  if (::inet_pton(AF_INET, public_address.c_str(), &pub) != 1 ||
      ::inet_pton(AF_INET, camera_address.c_str(), &cam) != 1)
    return Error{"gvsp-loss relay: bad address"};
  std::unique_ptr<GvspLossRelay> r(new GvspLossRelay());
  r->camera_ip_ = ntohl(cam.s_addr);
  r->loss_ratio_ = loss_ratio;
  r->rng_ = seed;
  r->gvcp_fd_ = UdpSocket(ntohl(pub.s_addr), kGvcpPort);
  r->upstream_fd_ = UdpSocket(ntohl(pub.s_addr), 0);
  r->gvsp_fd_ = UdpSocket(ntohl(cam.s_addr), 0);
  if (r->gvcp_fd_ < 0 || r->upstream_fd_ < 0 || r->gvsp_fd_ < 0)
    return Error{"gvsp-loss relay: cannot bind " + public_address + ":3956 and " + camera_address +
                 " (are both addresses of lo?)"};
  int size = 8 << 20;
  ::setsockopt(r->gvsp_fd_, SOL_SOCKET, SO_RCVBUF, &size, sizeof(size));
  GvspLossRelay* self = r.get();
  r->thread_ = std::thread([self] { self->Loop(); });
  return r;
}

GvspLossRelay::~GvspLossRelay() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  for (int fd : {gvcp_fd_, upstream_fd_, gvsp_fd_})
    if (fd >= 0) ::close(fd);
}

void GvspLossRelay::Loop() {
  sockaddr_in client{};       // the GVCP client (the capture)
  sockaddr_in destination{};  // where the client wants the stream
  sockaddr_in gvsp_local{};
  socklen_t length = sizeof(gvsp_local);
  ::getsockname(gvsp_fd_, reinterpret_cast<sockaddr*>(&gvsp_local), &length);
  const sockaddr_in camera = Address(camera_ip_, kGvcpPort);
  std::map<uint16_t, std::map<uint32_t, std::vector<uint8_t>>> frames;  // block -> packets
  std::deque<uint16_t> order;
  std::vector<uint8_t> buffer(65536);
  pollfd fds[3] = {{gvcp_fd_, POLLIN, 0}, {upstream_fd_, POLLIN, 0}, {gvsp_fd_, POLLIN, 0}};
  while (!stop_) {
    if (::poll(fds, 3, 100) <= 0) continue;
    if (fds[0].revents & POLLIN) {  // client -> camera
      socklen_t n = sizeof(client);
      const ssize_t size = ::recvfrom(gvcp_fd_, buffer.data(), buffer.size(), 0,
                                      reinterpret_cast<sockaddr*>(&client), &n);
      if (size >= static_cast<ssize_t>(kGvcpHeader)) {
        const uint16_t command = Get16(&buffer[2]);
        if (command == kPacketResendCmd && size >= static_cast<ssize_t>(kGvcpHeader + 12)) {
          const uint16_t block = Get16(&buffer[kGvcpHeader + 2]);
          const uint32_t first = Get32(&buffer[kGvcpHeader + 4]) & 0xffffff;
          const uint32_t last = Get32(&buffer[kGvcpHeader + 8]) & 0xffffff;
          const auto frame = frames.find(block);
          if (frame != frames.end()) {
            for (uint32_t id = first; id <= last && id - first < 100000; ++id) {
              const auto packet = frame->second.find(id);
              if (packet == frame->second.end()) continue;
              ::sendto(gvsp_fd_, packet->second.data(), packet->second.size(), 0,
                       reinterpret_cast<const sockaddr*>(&destination), sizeof(destination));
              ++resent_;
            }
          }
          continue;  // PACKETRESEND has no acknowledge
        }
        if (command == kWriteRegisterCmd) {
          for (ssize_t at = kGvcpHeader; at + 8 <= size; at += 8) {
            const uint32_t address = Get32(&buffer[at]);
            const uint32_t value = Get32(&buffer[at + 4]);
            if (address == kStreamChannelAddress) {
              destination.sin_family = AF_INET;
              destination.sin_addr.s_addr = htonl(value);
              Put32(&buffer[at + 4], ntohl(gvsp_local.sin_addr.s_addr));
            } else if (address == kStreamChannelPort) {
              destination.sin_port = htons(static_cast<uint16_t>(value & 0xffff));
              Put32(&buffer[at + 4], (value & 0xffff0000u) | ntohs(gvsp_local.sin_port));
            }
          }
        }
        ::sendto(upstream_fd_, buffer.data(), static_cast<size_t>(size), 0,
                 reinterpret_cast<const sockaddr*>(&camera), sizeof(camera));
      }
    }
    if (fds[1].revents & POLLIN) {  // camera -> client (acknowledges)
      const ssize_t size = ::recv(upstream_fd_, buffer.data(), buffer.size(), 0);
      if (size > 0)
        ::sendto(gvcp_fd_, buffer.data(), static_cast<size_t>(size), 0,
                 reinterpret_cast<const sockaddr*>(&client), sizeof(client));
    }
    if (fds[2].revents & POLLIN) {  // camera stream -> client, lossy
      const ssize_t size = ::recv(gvsp_fd_, buffer.data(), buffer.size(), 0);
      if (size < 8 || destination.sin_port == 0) continue;
      const uint16_t block = Get16(&buffer[2]);
      const uint32_t id = Get32(&buffer[4]) & 0xffffff;
      if (!frames.count(block)) {
        order.push_back(block);
        if (order.size() > kKeptFrames) frames.erase(order.front()), order.pop_front();
      }
      frames[block][id].assign(buffer.begin(), buffer.begin() + size);
      const double u = static_cast<double>(Hash(rng_++, 7, 11) >> 11) / 9007199254740992.0;
      if (u < loss_ratio_) {
        ++dropped_;
        continue;
      }
      ::sendto(gvsp_fd_, buffer.data(), static_cast<size_t>(size), 0,
               reinterpret_cast<const sockaddr*>(&destination), sizeof(destination));
    }
  }
}

}  // namespace ts::sim
