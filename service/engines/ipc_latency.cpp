// The three transports of `polyloc bench ipc` over one harness: the writer (this thread) sends
// on a fixed schedule, sleeping between messages; the reader (another thread, on another CPU when pinned) blocks until each message is there, copies
// it out and notes the time. Each message carries its number and its send time.
#include "engines/ipc_latency.hpp"

#include "shm/channel.hpp"
#include "shm/segment.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <sched.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <thread>

namespace polyloc::engines {
namespace {

int64_t nowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

[[noreturn]] void sysFail(const std::string& what) { throw std::runtime_error(what + ": " + std::strerror(errno)); }

// This thread on its CPU, at the configured scheduling class.
void placeThread(int cpu, int rt_priority) {
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  }
  if (rt_priority > 0) {
    sched_param p{};
    p.sched_priority = rt_priority;
    if ((errno = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p)) != 0)
      sysFail("bench ipc: SCHED_FIFO priority " + std::to_string(rt_priority));
  }
}

// Puts the calling thread's CPU set and scheduling class back as they were.
struct RestoreThread {
  cpu_set_t cpus;
  int policy = SCHED_OTHER;
  sched_param param{};
  RestoreThread() {
    pthread_getaffinity_np(pthread_self(), sizeof cpus, &cpus);
    pthread_getschedparam(pthread_self(), &policy, &param);
  }
  ~RestoreThread() {
    pthread_setschedparam(pthread_self(), policy, &param);
    pthread_setaffinity_np(pthread_self(), sizeof cpus, &cpus);
  }
};

void sleepUntil(int64_t t) {
  const timespec ts{static_cast<time_t>(t / 1'000'000'000), static_cast<long>(t % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// send(msg) delivers one message; receive(buf) blocks until one is in buf (false: the channel
// went quiet for seconds, i.e. messages were lost, or it was closed); unblock() makes a blocked
// receive return when the writer fails.
template <class Send, class Receive>
IpcSamples measure(const IpcLatencyConfig& c, Send&& send, Receive&& receive,
                             const std::function<void()>& unblock, const std::function<void(double)>& progress) {
  if (c.bytes < 16) throw std::runtime_error("bench ipc: messages need at least 16 bytes (number and send time)");
  const size_t total = c.warmup + c.messages;
  std::vector<int64_t> latency(total, -1), send_time(total, 0);
  std::atomic<bool> ready{false};
  std::exception_ptr reader_error, writer_error;
  std::thread reader([&] {
    std::vector<uint8_t> buf(c.bytes);
    try {
      placeThread(c.reader_cpu, c.rt_priority);
      ready = true;
      for (uint64_t seq = 0; seq + 1 < total;) {
        if (!receive(buf)) break;
        const int64_t t = nowNs();
        int64_t sent = 0;
        std::memcpy(&seq, buf.data(), sizeof seq);
        std::memcpy(&sent, buf.data() + 8, sizeof sent);
        if (seq < total) latency[seq] = t - sent;
      }
    } catch (...) {
      reader_error = std::current_exception();
      ready = true;
    }
  });
  while (!ready) std::this_thread::yield();
  const RestoreThread restore;  // the writer is the caller's thread
  std::vector<uint8_t> msg(c.bytes);
  for (size_t i = 16; i < msg.size(); ++i) msg[i] = static_cast<uint8_t>(i * 31);
  const int64_t period = static_cast<int64_t>(c.period_us * 1000);
  const int64_t start = nowNs() + 2'000'000;  // the reader is asleep in its first wait by then
  try {
    if (reader_error) std::rethrow_exception(reader_error);
    placeThread(c.writer_cpu, c.rt_priority);
    for (uint64_t i = 0; i < total; ++i) {
      // Sleeping, not spinning, between messages: the send time is taken after the wake-up, so
      // the writer's timer jitter changes the spacing, not the latency.
      sleepUntil(start + static_cast<int64_t>(i) * period);
      const int64_t t = nowNs();
      std::memcpy(msg.data(), &i, sizeof i);
      std::memcpy(msg.data() + 8, &t, sizeof t);
      send(msg);
      send_time[i] = nowNs() - t;
      if (progress && i % 1000 == 0) progress(static_cast<double>(i) / static_cast<double>(total));
    }
  } catch (...) {
    writer_error = std::current_exception();
    unblock();
  }
  reader.join();
  if (writer_error) std::rethrow_exception(writer_error);
  if (reader_error) std::rethrow_exception(reader_error);
  IpcSamples counted;
  for (size_t i = c.warmup; i < total; ++i)
    if (latency[i] >= 0) {
      counted.latency_ns.push_back(latency[i]);
      counted.send_ns.push_back(send_time[i]);
    }
  return counted;
}

void sendAll(int fd, const std::vector<uint8_t>& msg, const char* what) {
  for (size_t done = 0; done < msg.size();) {
    const ssize_t n = ::send(fd, msg.data() + done, msg.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno != EINTR) sysFail(std::string(what) + " send");
    done += n > 0 ? static_cast<size_t>(n) : 0;
  }
}

bool recvAll(int fd, std::vector<uint8_t>& buf, const char* what) {
  for (size_t done = 0; done < buf.size();) {
    const ssize_t n = ::recv(fd, buf.data() + done, buf.size() - done, 0);
    if (n == 0) return false;
    if (n < 0 && errno != EINTR) sysFail(std::string(what) + " recv");
    done += n > 0 ? static_cast<size_t>(n) : 0;
  }
  return true;
}

// A connected stream socket pair: writer end first. Both ends close with the object.
struct SocketPair {
  int w = -1, r = -1;
  ~SocketPair() {
    if (w >= 0) close(w);
    if (r >= 0) close(r);
  }
};

IpcSamples overSockets(const IpcLatencyConfig& c, SocketPair& s, const char* what,
                                 const std::function<void(double)>& progress) {
  // Room for a few messages on both ends: the writer never blocks on a full buffer.
  const int buf = static_cast<int>(std::min<uint64_t>(4ull * c.bytes + 65536, 1u << 24));
  setsockopt(s.w, SOL_SOCKET, SO_SNDBUF, &buf, sizeof buf);
  setsockopt(s.r, SOL_SOCKET, SO_RCVBUF, &buf, sizeof buf);
  auto result = measure(
      c, [&](const std::vector<uint8_t>& m) { sendAll(s.w, m, what); },
      [&](std::vector<uint8_t>& b) { return recvAll(s.r, b, what); }, [&] { shutdown(s.w, SHUT_RDWR); }, progress);
  return result;
}

}  // namespace

IpcSamples shmLatency(const IpcLatencyConfig& c, const std::function<void(double)>& progress) {
  const std::string instance = "bench-ipc-" + std::to_string(getpid());
  shm::ChannelSpec spec;
  spec.name = "scan/bench";
  spec.kind = POLYLOC_KIND_RANGES;
  spec.direction = POLYLOC_DIR_INPUT;  // the controller -> polylocd path: doorbell included
  // Room for 200 ms of messages (at most 64 MiB): a socket buffers what its reader has not
  // taken (and then blocks the writer); a ring of that depth lets a reader that was kept off its
  // CPU for a while catch up too, instead of losing messages the sockets would have kept.
  const uint64_t want = static_cast<uint64_t>(200'000 / c.period_us) + 1;
  const uint64_t fit = std::max<uint64_t>(64, (64ull << 20) / (c.bytes + 128));
  spec.slot_count = static_cast<uint32_t>(std::clamp<uint64_t>(std::bit_ceil(want), 64, std::bit_floor(fit)));
  spec.payload_max = c.bytes;
  auto seg = shm::Segment::create(instance, {spec});
  seg.ready();
  shm::Segment::unlink(instance);  // nobody else attaches; the mapping lives on
  shm::Writer w(seg, 0);
  shm::Reader r(seg, 0);
  return measure(
      c, [&](const std::vector<uint8_t>& m) { w.write(m.data(), static_cast<uint32_t>(m.size()), 0); },
      [&](std::vector<uint8_t>& b) {
        for (;;) {
          if (r.next(b)) return true;
          if (!r.wait(2'000'000'000, c.spin_ns)) return false;
        }
      },
      [] {}, progress);  // a blocked reader gives up at its 2 s timeout
}

IpcSamples udsLatency(const IpcLatencyConfig& c, const std::function<void(double)>& progress) {
  SocketPair s;
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0) sysFail("uds socketpair");
  s.w = fds[0];
  s.r = fds[1];
  return overSockets(c, s, "uds", progress);
}

IpcSamples tcpLatency(const IpcLatencyConfig& c, const std::function<void(double)>& progress) {
  SocketPair s;
  const int listener = socket(AF_INET, SOCK_STREAM, 0);
  if (listener < 0) sysFail("tcp socket");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (bind(listener, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || listen(listener, 1) != 0 ||
      getsockname(listener, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    close(listener);
    sysFail("tcp bind/listen on 127.0.0.1");
  }
  s.w = socket(AF_INET, SOCK_STREAM, 0);
  if (s.w < 0 || connect(s.w, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(listener);
    sysFail("tcp connect to 127.0.0.1");
  }
  s.r = accept(listener, nullptr, nullptr);
  close(listener);
  if (s.r < 0) sysFail("tcp accept");
  const int one = 1;
  setsockopt(s.w, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  setsockopt(s.r, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return overSockets(c, s, "tcp", progress);
}

}  // namespace polyloc::engines
