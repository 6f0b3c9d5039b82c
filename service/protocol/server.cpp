#include "protocol/server.hpp"

#include "protocol/connection.hpp"
#include "protocol/dispatcher.hpp"
#include "protocol/log_limit.hpp"
#include "protocol/sockets.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

namespace polyloc::protocol {
namespace {

using Clock = Connection::Clock;
using Ms = std::chrono::milliseconds;

// Settings that cannot work are refused at start, by name.
void validate(const ServerConfig& c) {
  const auto need = [](bool ok, const char* what, long long value) {
    if (!ok) throw std::invalid_argument(fmt::format("protocol server: {} (it is {})", what, value));
  };
  need(c.max_clients >= 1, "max_clients must be at least 1", c.max_clients);
  need(c.max_frame_bytes >= kMinFrameBytes, "max_frame_bytes must be at least 16", c.max_frame_bytes);
  need(c.frame_timeout_ms > 0, "frame_timeout_ms must be positive", c.frame_timeout_ms);
  need(c.first_frame_timeout_ms > 0, "first_frame_timeout_ms must be positive", c.first_frame_timeout_ms);
  need(c.idle_timeout_ms >= 0, "idle_timeout_ms must be 0 (never) or positive", c.idle_timeout_ms);
  need(c.max_queued_bytes > 0, "max_queued_bytes must be positive", static_cast<long long>(c.max_queued_bytes));
  need(c.max_frame_errors >= 1, "max_frame_errors must be at least 1", c.max_frame_errors);
  need(c.close_linger_ms >= 0, "close_linger_ms must not be negative", c.close_linger_ms);
}

// Reasons after which nothing more is sent: the connection goes at once.
bool abrupt(CloseReason r) { return r == CloseReason::Slow || r == CloseReason::IoError || r == CloseReason::Stopped; }

}  // namespace

struct Server::Impl {
  ServerConfig cfg;
  ControlHandler& handler;
  int listen_fd = -1, wake_fd = -1;
  uint16_t port = 0;
  std::thread thread;
  std::atomic<bool> stopping{false}, running{false};
  mutable std::mutex mu;
  ServerCounters counters;
  std::vector<std::unique_ptr<Connection>> conns;  // server thread only
  LogLimiter limiter;

  Impl(ServerConfig c, ControlHandler& h) : cfg(std::move(c)), handler(h) {}

  void count(uint64_t ServerCounters::*field, uint64_t n = 1) {
    std::lock_guard lock(mu);
    counters.*field += n;
  }

  template <class... Args>
  void warn(const std::string& kind, fmt::format_string<Args...> f, Args&&... args) {
    uint64_t suppressed = 0;
    if (!limiter.allow(kind, suppressed)) return;
    const std::string msg = fmt::format(f, std::forward<Args>(args)...);
    if (suppressed)
      spdlog::warn("protocol: {} ({} similar messages suppressed)", msg, suppressed);
    else
      spdlog::warn("protocol: {}", msg);
  }

  void beginClose(Connection& c, CloseReason why, Clock::time_point now) {
    if (c.closing != CloseReason::None) return;
    c.closing = why;
    c.close_by = now + Ms(cfg.close_linger_ms);
  }

  void queue(Connection& c, const Frame& reply, Clock::time_point now) {
    c.queue(reply);
    count(&ServerCounters::replies);
    if (c.queued() <= cfg.max_queued_bytes) return;
    flush(c);  // the socket may take some now
    if (c.queued() > cfg.max_queued_bytes && c.closing == CloseReason::None) {
      warn("slow", "{}: {} reply bytes unread (limit {}), closing", c.peer(), c.queued(), cfg.max_queued_bytes);
      beginClose(c, CloseReason::Slow, now);
    }
  }

  void countStatus(Status s) {
    if (s == Status::UnknownCommand)
      count(&ServerCounters::unknown_command);
    else if (s == Status::BadSize || s == Status::BadArgument)
      count(&ServerCounters::bad_request);
    else if (s == Status::NotAvailable)
      count(&ServerCounters::not_available);
    else if (s == Status::Internal)
      count(&ServerCounters::handler_failures);
  }

  void frameError(Connection& c, const ParseResult& r, Clock::time_point now) {
    static constexpr uint64_t ServerCounters::*fields[] = {nullptr, &ServerCounters::bad_magic,
                                                           &ServerCounters::bad_frame_size,
                                                           &ServerCounters::frame_too_large, &ServerCounters::bad_crc};
    count(fields[static_cast<int>(r.error)]);
    warn(toString(r.error), "{}: {}", c.peer(), r.message());
    const uint32_t detail = r.error == FrameError::BadCrc ? r.command : r.size;
    queue(c, frameErrorReply(toStatus(r.error), detail), now);
    if (++c.frame_errors >= cfg.max_frame_errors) beginClose(c, CloseReason::FrameErrors, now);
  }

  void serveFrames(Connection& c, bool was_mid, Clock::time_point now) {
    bool completed = false;
    while (c.closing == CloseReason::None) {
      ParseResult r = c.parser().next();
      if (r.kind == ParseResult::Kind::NeedMore) break;
      completed = true;
      if (r.kind == ParseResult::Kind::Error) {
        frameError(c, r, now);
        continue;
      }
      count(&ServerCounters::frames);
      ++c.frames;
      Dispatched d = dispatch(r.frame, handler);
      if (!d.failure.empty()) warn("handler", "{}: {} failed: {}", c.peer(), commandName(r.frame.command), d.failure);
      countStatus(replyStatus(d.reply));
      queue(c, d.reply, now);
    }
    if (completed || !was_mid) c.frame_started = now;
  }

  void flush(Connection& c) {
    size_t n = 0;
    const Connection::Io io = c.flush(n);
    count(&ServerCounters::bytes_out, n);
    if (io == Connection::Io::Error) c.closing = CloseReason::IoError;  // whatever it was: nothing more can be sent
  }

  void onReadable(Connection& c, Clock::time_point now) {
    const bool was_mid = c.parser().midFrame();
    size_t n = 0;
    switch (c.readSome(c.closing == CloseReason::None, n)) {
      case Connection::Io::Data:
        count(&ServerCounters::bytes_in, n);
        c.last_rx = now;
        serveFrames(c, was_mid, now);
        break;
      case Connection::Io::Eof:
        c.peer_eof = true;
        beginClose(c, CloseReason::Peer, now);  // replies still queued are sent first
        break;
      case Connection::Io::Error: beginClose(c, CloseReason::IoError, now); break;
      case Connection::Io::WouldBlock: break;
    }
  }

  void checkTimers(Connection& c, Clock::time_point now) {
    if (c.closing != CloseReason::None) return;
    if (c.parser().midFrame() && now - c.frame_started > Ms(cfg.frame_timeout_ms)) {
      count(&ServerCounters::frame_timeouts);
      warn("timeout", "{}: frame not completed within {} ms ({} bytes held), closing", c.peer(), cfg.frame_timeout_ms,
           c.parser().buffered());
      queue(c, frameErrorReply(Status::FrameTimeout), now);
      beginClose(c, CloseReason::FrameTimeout, now);
    } else if (c.frames == 0 && c.frame_errors == 0 && now - c.connected > Ms(cfg.first_frame_timeout_ms)) {
      // A client that connects and says nothing holds one of max_clients places: without this,
      // 16 of them lock every other client out for the idle timeout.
      count(&ServerCounters::frame_timeouts);
      warn("timeout", "{}: no whole frame within {} ms of connecting, closing", c.peer(), cfg.first_frame_timeout_ms);
      queue(c, frameErrorReply(Status::FrameTimeout), now);
      beginClose(c, CloseReason::FrameTimeout, now);
    } else if (cfg.idle_timeout_ms > 0 && now - c.last_rx > Ms(cfg.idle_timeout_ms)) {
      spdlog::info("protocol: {}: idle for {} ms, closing", c.peer(), cfg.idle_timeout_ms);
      beginClose(c, CloseReason::Idle, now);
    }
  }

  // A closing connection sends what is queued, shuts its side, then reads (and drops) until the
  // peer closes or the linger time is up: closing with unread input would reset the connection
  // and could destroy the error reply before the peer reads it.
  bool finished(Connection& c, Clock::time_point now) {
    if (c.closing == CloseReason::None) return false;
    if (abrupt(c.closing)) return true;
    if (c.queued() > 0) return now >= c.close_by;
    if (c.peer_eof) return true;
    if (!c.write_shut) c.shutdownWrite(), c.close_by = now + Ms(cfg.close_linger_ms);
    return now >= c.close_by;
  }

  void closed(const Connection& c) {
    static constexpr uint64_t ServerCounters::*fields[] = {nullptr,
                                                           &ServerCounters::closed_peer,
                                                           &ServerCounters::closed_frame_errors,
                                                           &ServerCounters::closed_frame_timeout,
                                                           &ServerCounters::closed_idle,
                                                           &ServerCounters::closed_slow,
                                                           &ServerCounters::closed_io_error,
                                                           &ServerCounters::closed_busy,
                                                           &ServerCounters::closed_stopped};
    {
      std::lock_guard lock(mu);
      counters.*fields[static_cast<int>(c.closing)] += 1;
      counters.open -= 1;
    }
    spdlog::debug("protocol: {} closed ({})", c.peer(), toString(c.closing));
  }

  void acceptAll(Clock::time_point now) {
    for (;;) {
      sockaddr_storage a{};
      socklen_t len = sizeof a;
      const int fd = accept4(listen_fd, reinterpret_cast<sockaddr*>(&a), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR && errno != ECONNABORTED)
          warn("accept", "accept failed: {}", std::strerror(errno));
        if (errno == EINTR || errno == ECONNABORTED) continue;
        return;
      }
      const int one = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);  // small replies, sent at once
      auto c = std::make_unique<Connection>(fd, peerName(a, len), cfg.max_frame_bytes, now);
      {
        std::lock_guard lock(mu);
        counters.accepted += 1, counters.open += 1;
      }
      if (conns.size() >= static_cast<size_t>(cfg.max_clients)) {
        warn("busy", "{}: {} clients already, refusing", c->peer(), conns.size());
        queue(*c, frameErrorReply(Status::Busy), now);
        beginClose(*c, CloseReason::Busy, now);
      }
      spdlog::debug("protocol: {} connected", c->peer());
      conns.push_back(std::move(c));
    }
  }

  int pollTimeoutMs(Clock::time_point now) const {
    Clock::time_point next = now + Ms(1000);
    for (const auto& c : conns) {
      if (c->closing != CloseReason::None)
        next = std::min(next, c->close_by);
      else if (c->parser().midFrame())
        next = std::min(next, c->frame_started + Ms(cfg.frame_timeout_ms + 1));
      else if (c->frames == 0 && c->frame_errors == 0)
        next = std::min(next, c->connected + Ms(cfg.first_frame_timeout_ms + 1));
      else if (cfg.idle_timeout_ms > 0)
        next = std::min(next, c->last_rx + Ms(cfg.idle_timeout_ms + 1));
    }
    return static_cast<int>(std::clamp<int64_t>(std::chrono::ceil<Ms>(next - now).count(), 0, 1000));
  }

  // One poll() and what it reported: accept, read and answer, write, timers, closes.
  void step(std::vector<pollfd>& fds) {
    fds.assign({{wake_fd, POLLIN, 0}, {listen_fd, POLLIN, 0}});
    for (const auto& c : conns) {
      const short out = c->queued() > 0 ? POLLOUT : 0;
      fds.push_back({c->fd(), static_cast<short>((c->peer_eof ? 0 : POLLIN) | out), 0});
    }
    if (::poll(fds.data(), fds.size(), pollTimeoutMs(Clock::now())) < 0 && errno != EINTR)
      warn("poll", "poll failed: {}", std::strerror(errno));
    if (stopping) return;
    const Clock::time_point now = Clock::now();
    if (fds[1].revents & POLLIN) acceptAll(now);
    for (size_t i = 0; i + 2 < fds.size() && i < conns.size(); ++i) {
      Connection& c = *conns[i];
      const short ev = fds[i + 2].revents;
      if (ev & (POLLIN | POLLHUP | POLLERR)) onReadable(c, now);
      if (c.queued() > 0 && !abrupt(c.closing)) flush(c);
    }
    for (auto& c : conns) checkTimers(*c, now);
    std::erase_if(conns, [&](const std::unique_ptr<Connection>& c) {
      if (!finished(*c, now)) return false;
      closed(*c);
      return true;
    });
  }

  void loop() {
    std::vector<pollfd> fds;
    while (!stopping) {
      try {
        step(fds);
      } catch (const std::exception& e) {  // e.g. out of memory: the server goes on
        warn("internal", "server loop: {}", e.what());
      }
    }
    for (auto& c : conns) c->closing = CloseReason::Stopped, closed(*c);
    conns.clear();
  }
};

Server::Server(ServerConfig config, ControlHandler& handler)
    : impl_(std::make_unique<Impl>(std::move(config), handler)) {}

Server::~Server() { stop(); }

void Server::start() {
  Impl& m = *impl_;
  if (m.running) throw std::logic_error("protocol server: already running");
  validate(m.cfg);
  m.listen_fd = listenOn(m.cfg.bind_address, m.cfg.port, m.port);
  m.wake_fd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (m.wake_fd < 0) {
    ::close(m.listen_fd);
    throw std::runtime_error(fmt::format("protocol server: eventfd: {}", std::strerror(errno)));
  }
  m.stopping = false;
  m.running = true;
  m.thread = std::thread([&m] { m.loop(); });
  spdlog::info("protocol: listening on {}:{}", m.cfg.bind_address, m.port);
}

void Server::stop() {
  Impl& m = *impl_;
  if (!m.running.exchange(false)) return;
  m.stopping = true;
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t w = ::write(m.wake_fd, &one, sizeof one);
  m.thread.join();
  ::close(m.listen_fd), ::close(m.wake_fd);
  m.listen_fd = m.wake_fd = -1;
}

bool Server::running() const { return impl_->running; }
uint16_t Server::port() const { return impl_->port; }
const ServerConfig& Server::config() const { return impl_->cfg; }

ServerCounters Server::counters() const {
  std::lock_guard lock(impl_->mu);
  return impl_->counters;
}

}  // namespace polyloc::protocol
