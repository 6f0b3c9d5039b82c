#include "protocol/sockets.hpp"

#include <fmt/core.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <netdb.h>
#include <netinet/in.h>
#include <unistd.h>

namespace polyloc::protocol {

std::string peerName(const sockaddr_storage& a, socklen_t len) {
  char host[NI_MAXHOST], serv[NI_MAXSERV];
  if (getnameinfo(reinterpret_cast<const sockaddr*>(&a), len, host, sizeof host, serv, sizeof serv,
                  NI_NUMERICHOST | NI_NUMERICSERV) != 0)
    return "?";
  return a.ss_family == AF_INET6 ? fmt::format("[{}]:{}", host, serv) : fmt::format("{}:{}", host, serv);
}

int listenOn(const std::string& address, uint16_t port, uint16_t& bound) {
  const std::string where = fmt::format("{}:{}", address, port);
  addrinfo hints{}, *res = nullptr;
  hints.ai_family = AF_UNSPEC, hints.ai_socktype = SOCK_STREAM, hints.ai_flags = AI_PASSIVE | AI_NUMERICHOST;
  if (const int e = getaddrinfo(address.c_str(), std::to_string(port).c_str(), &hints, &res); e != 0)
    throw std::runtime_error(fmt::format("protocol server: bad bind address {}: {}", where, gai_strerror(e)));
  const int fd = ::socket(res->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  const int one = 1;
  if (fd >= 0) setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (fd < 0 || ::bind(fd, res->ai_addr, res->ai_addrlen) != 0 || ::listen(fd, 64) != 0) {
    const int e = errno;
    if (fd >= 0) ::close(fd);
    freeaddrinfo(res);
    throw std::runtime_error(fmt::format("protocol server: cannot listen on {}: {}", where, std::strerror(e)));
  }
  freeaddrinfo(res);
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  bound = ntohs(a.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&a)->sin6_port
                                        : reinterpret_cast<sockaddr_in*>(&a)->sin_port);
  return fd;
}

}  // namespace polyloc::protocol
