#include "protocol/client.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace polyloc::protocol {
namespace {

using Clock = std::chrono::steady_clock;

int msLeft(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left < 0 ? 0 : static_cast<int>(left);
}

// Waits for `events` on fd until the deadline; false on timeout.
bool waitFor(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    pollfd p{fd, events, 0};
    const int r = ::poll(&p, 1, msLeft(deadline));
    if (r > 0) return true;
    if (r == 0) return false;
    if (errno != EINTR) return false;
  }
}

// Connects to one resolved address within the deadline; the socket stays non-blocking.
int connectTo(const addrinfo& a, Clock::time_point deadline, int& err) {
  const int fd = ::socket(a.ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return err = errno, -1;
  if (::connect(fd, a.ai_addr, a.ai_addrlen) == 0) return fd;
  if (errno == EINPROGRESS) {
    if (!waitFor(fd, POLLOUT, deadline))
      err = ETIMEDOUT;
    else {
      socklen_t len = sizeof err;
      getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
      if (err == 0) return fd;
    }
  } else {
    err = errno;
  }
  ::close(fd);
  return -1;
}

}  // namespace

Client::Client(const std::string& host, uint16_t port, ClientOptions options)
    : where_(host + ":" + std::to_string(port)), opt_(options), parser_(options.max_frame_bytes) {
  addrinfo hints{}, *res = nullptr;
  hints.ai_family = AF_UNSPEC, hints.ai_socktype = SOCK_STREAM;
  if (const int e = getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res); e != 0)
    throw std::runtime_error("cannot resolve " + where_ + ": " + gai_strerror(e));
  const auto deadline = Clock::now() + std::chrono::milliseconds(opt_.timeout_ms);
  int err = 0;
  for (addrinfo* a = res; a && fd_ < 0; a = a->ai_next) fd_ = connectTo(*a, deadline, err);
  freeaddrinfo(res);
  if (fd_ < 0) throw std::runtime_error("cannot connect to " + where_ + ": " + std::strerror(err));
  const int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

Client::~Client() {
  if (fd_ >= 0) ::close(fd_);
}

void Client::sendBytes(std::span<const uint8_t> bytes) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(opt_.timeout_ms);
  size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n > 0) {
      sent += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (!waitFor(fd_, POLLOUT, deadline))
        throw std::runtime_error("sending to " + where_ + ": timed out after " + std::to_string(opt_.timeout_ms) +
                                 " ms");
      continue;
    }
    throw std::runtime_error("sending to " + where_ + ": " + std::strerror(errno));
  }
}

std::optional<Frame> Client::receive(int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  uint8_t buf[16384];
  for (;;) {
    ParseResult r = parser_.next();
    if (r.kind == ParseResult::Kind::Frame) return std::move(r.frame);
    if (r.kind == ParseResult::Kind::Error) throw std::runtime_error("reply from " + where_ + ": " + r.message());
    if (!waitFor(fd_, POLLIN, deadline)) return std::nullopt;
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n > 0)
      parser_.push({buf, static_cast<size_t>(n)});
    else if (n == 0)
      throw std::runtime_error("connection closed by " + where_);
    else if (errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK)
      throw std::runtime_error("receiving from " + where_ + ": " + std::strerror(errno));
  }
}

Frame Client::call(uint32_t command, std::span<const uint32_t> data) {
  sendBytes(encodeFrame(command, data));
  const auto deadline = Clock::now() + std::chrono::milliseconds(opt_.timeout_ms);
  for (;;) {
    auto f = receive(msLeft(deadline));
    if (!f) throw std::runtime_error("no reply from " + where_ + " within " + std::to_string(opt_.timeout_ms) + " ms");
    // A late reply to an earlier call that timed out is not this call's.
    if (f->command == replyId(command) || f->command == cmd::FRAME_ERROR) return std::move(*f);
  }
}

bool Client::waitClosed(int timeout_ms) {
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  uint8_t buf[16384];
  for (;;) {
    if (!waitFor(fd_, POLLIN, deadline)) return false;
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n == 0) return true;
    if (n < 0 && errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK) return true;  // reset
  }
}

}  // namespace polyloc::protocol
