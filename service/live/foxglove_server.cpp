// The server's state lives on its asio thread: clients, subscriptions and latched messages are
// touched only there (publish() posts to it), so nothing but the subscriber counts and the
// statistics needs a lock or an atomic.
#include "live/foxglove_server.hpp"

#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <unistd.h>

namespace polyloc::live {
namespace {

using WsServer = websocketpp::server<websocketpp::config::asio>;
using Hdl = websocketpp::connection_hdl;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr const char* kSubprotocol = "foxglove.websocket.v1";
constexpr uint8_t kOpMessageData = 1;

struct Client {
  Hdl hdl;
  std::string name;                         // address:port, for the log
  std::map<uint32_t, uint32_t> subs;        // subscription id -> channel id
  std::map<uint32_t, uint32_t> owed;        // subscription id -> latched channel not yet sent (queue was full)
  double tokens = 0;                        // client messages it may still send now (rate limit)
  Clock::time_point refilled{};
  Clock::time_point over_since{};           // queue over the limit since (epoch: not over)
  int bad = 0;
  bool closing = false;                     // disconnected as too slow: nothing more goes to it
};

}  // namespace

struct FoxgloveServer::Impl {
  ServerConfig cfg;
  std::vector<ChannelSpec> channels;             // id = index + 1
  std::unique_ptr<std::atomic<int>[]> subscribers;  // per channel: subscriptions now
  WsServer ws;
  std::thread thread;
  std::map<Hdl, Client, std::owner_less<Hdl>> clients;
  std::vector<Hdl> pending_conns;  // accepted, handshake not done: bounded by max_pending
  std::unique_ptr<asio::steady_timer> accept_pause;  // after a failed accept: retry later, never spin
  std::map<uint32_t, std::pair<uint64_t, std::shared_ptr<const std::vector<uint8_t>>>> latched;
  uint16_t bound_port = 0;
  std::atomic<bool> running{false};  // read by publishers' threads
  bool warned_pending = false, warned_accept = false;  // one warning per episode, not per connection
  // Messages handed over and not yet fanned out: bounded, so that a server thread starved of CPU
  // cannot make the publisher's memory grow; beyond it messages are dropped (counted).
  std::atomic<int> pending{0};
  static constexpr int kMaxPending = 1000;
  mutable std::mutex stats_m;
  ServerStats st;

  explicit Impl(ServerConfig c) : cfg(std::move(c)) {}

  template <class F> void count(F&& f) { std::lock_guard l(stats_m); f(st); }

  void status(Client& c, int level, const std::string& message) {
    json j{{"op", "status"}, {"level", level}, {"message", message}};
    websocketpp::lib::error_code ec;
    ws.send(c.hdl, j.dump(), websocketpp::frame::opcode::text, ec);
  }

  void bad(Client& c, const std::string& why) {
    count([](ServerStats& s) { ++s.bad_messages; });
    ++c.bad;
    spdlog::warn("live view: client {}: {}", c.name, why);
    status(c, 2, why);
    if (c.bad >= cfg.max_bad_messages) {
      websocketpp::lib::error_code ec;
      ws.close(c.hdl, websocketpp::close::status::policy_violation, "too many malformed messages", ec);
    }
  }

  json advertisement() const {
    json list = json::array();
    for (size_t i = 0; i < channels.size(); ++i) {
      const ChannelSpec& c = channels[i];
      list.push_back({{"id", i + 1}, {"topic", c.topic}, {"encoding", c.encoding}, {"schemaName", c.schema_name},
                      {"schema", c.schema}, {"schemaEncoding", c.schema_encoding}});
    }
    return json{{"op", "advertise"}, {"channels", list}};
  }

  // Sends one message frame to a client's subscription; false when the client's queue is full.
  // Latched messages too: a forced send would let one client queue the map without bound.
  bool sendTo(Client& c, uint32_t sub, uint64_t stamp, const std::vector<uint8_t>& payload) {
    if (c.closing) return false;
    websocketpp::lib::error_code hec;
    WsServer::connection_ptr con = ws.get_con_from_hdl(c.hdl, hec);
    if (hec) return false;
    const auto now = Clock::now();
    // An empty queue takes any one message (a map bigger than the limit still goes, alone).
    const size_t queued = con->get_buffered_amount();
    if (queued > 0 && queued + payload.size() > cfg.max_queue_bytes) {
      count([](ServerStats& s) { ++s.messages_dropped; });
      if (c.over_since == Clock::time_point{}) c.over_since = now;
      if (now - c.over_since > std::chrono::duration<double>(cfg.stall_timeout_s)) {
        spdlog::warn("live view: client {} disconnected: it took nothing for {:.1f} s", c.name, cfg.stall_timeout_s);
        count([](ServerStats& s) { ++s.disconnected_slow; });
        // A stalled client never reads a close frame either: drop the connection outright. Later,
        // not here: the close handler erases the client while the caller iterates over clients.
        c.closing = true;
        asio::post(ws.get_io_service(), [this, h = c.hdl] {
          websocketpp::lib::error_code ec;
          if (WsServer::connection_ptr gone = ws.get_con_from_hdl(h, ec); !ec) gone->terminate(ec);
        });
      }
      return false;
    }
    c.over_since = {};
    // opcode, subscription id, timestamp, payload: written once into the connection's message.
    uint8_t head[13];
    head[0] = kOpMessageData;
    std::memcpy(&head[1], &sub, 4);  // little endian (x86, ARM: the hosts polylocd runs on)
    std::memcpy(&head[5], &stamp, 8);
    WsServer::message_ptr msg = con->get_message(websocketpp::frame::opcode::binary, sizeof head + payload.size());
    msg->append_payload(head, sizeof head);
    msg->append_payload(payload.data(), payload.size());
    const websocketpp::lib::error_code ec = con->send(msg);
    if (!ec) count([](ServerStats& s) { ++s.messages_sent; });
    return !ec;
  }

  void fanOut(uint32_t channel, uint64_t stamp, const std::shared_ptr<const std::vector<uint8_t>>& payload) {
    if (channels[channel - 1].latched) latched[channel] = {stamp, payload};
    for (auto& [hdl, c] : clients) {
      payOwed(c);
      for (const auto& [sub, ch] : c.subs)
        if (ch == channel) {
          if (sendTo(c, sub, stamp, *payload)) c.owed.erase(sub);  // the newer message replaces the owed one
        }
    }
  }

  // A latched message that found the client's queue full is sent when there is room again.
  void payOwed(Client& c) {
    for (auto it = c.owed.begin(); it != c.owed.end();) {
      const auto l = latched.find(it->second);
      if (l == latched.end() || sendTo(c, it->first, l->second.first, *l->second.second)) it = c.owed.erase(it);
      else break;  // still full: the rest wait too
    }
  }

  void sendLatched(Client& c, uint32_t sub, uint32_t ch) {
    const auto l = latched.find(ch);
    if (l == latched.end()) return;
    if (!sendTo(c, sub, l->second.first, *l->second.second)) c.owed[sub] = ch;
  }

  // Token bucket: bursts of max_client_rate messages, max_client_rate per second after that.
  bool withinRate(Client& c) {
    const auto now = Clock::now();
    const double burst = std::max(1.0, cfg.max_client_rate);
    if (c.refilled == Clock::time_point{}) c.tokens = burst;
    else c.tokens = std::min(burst, c.tokens + std::chrono::duration<double>(now - c.refilled).count() * cfg.max_client_rate);
    c.refilled = now;
    if (c.tokens < 1) return false;
    c.tokens -= 1;
    return true;
  }

  // Ids are uint32 on the wire (message frames carry 4 bytes): a larger one is refused, not wrapped.
  static bool isId(const json& v) {
    return v.is_number_unsigned() && v.get<uint64_t>() <= std::numeric_limits<uint32_t>::max();
  }

  void subscribe(Client& c, const json& list) {
    if (!list.is_array()) return bad(c, "subscribe: 'subscriptions' must be an array");
    for (const json& s : list) {
      if (!s.is_object() || !s.contains("id") || !s.contains("channelId") || !isId(s["id"]) || !isId(s["channelId"]))
        return bad(c, "subscribe: each subscription needs 'id' and 'channelId', integers in 0..4294967295");
      const uint32_t sub = s["id"].get<uint32_t>(), ch = s["channelId"].get<uint32_t>();
      if (ch == 0 || ch > channels.size()) {
        bad(c, "subscribe: no channel " + std::to_string(ch));
        continue;
      }
      if (c.subs.count(sub)) {
        bad(c, "subscribe: subscription id " + std::to_string(sub) + " is in use");
        continue;
      }
      if (int(c.subs.size()) >= cfg.max_subscriptions)  // the rest of the list too: one answer
        return bad(c, "subscribe: at most " + std::to_string(cfg.max_subscriptions) + " subscriptions per client");
      // The latched message once per client and channel: a second id on the channel gets what
      // comes next, not another copy of the map.
      const bool had = std::any_of(c.subs.begin(), c.subs.end(), [ch](const auto& e) { return e.second == ch; });
      c.subs[sub] = ch;
      ++subscribers[ch - 1];
      if (!had) sendLatched(c, sub, ch);
    }
  }

  void unsubscribe(Client& c, const json& list) {
    if (!list.is_array()) return bad(c, "unsubscribe: 'subscriptionIds' must be an array");
    for (const json& s : list) {
      if (!isId(s)) return bad(c, "unsubscribe: subscription ids are integers in 0..4294967295");
      auto it = c.subs.find(s.get<uint32_t>());
      if (it == c.subs.end()) {
        bad(c, "unsubscribe: no subscription " + std::to_string(s.get<uint32_t>()));
        continue;
      }
      --subscribers[it->second - 1];
      c.owed.erase(it->first);
      c.subs.erase(it);
    }
  }

  void onMessage(Hdl h, WsServer::message_ptr m) {
    auto it = clients.find(h);
    if (it == clients.end()) return;
    Client& c = it->second;
    if (!withinRate(c)) {
      count([](ServerStats& s) { ++s.rate_limited; });
      return bad(c, "too many messages: at most " + fmt::format("{:g}", cfg.max_client_rate) + " per second (polylocd.live.max_client_rate)");
    }
    if (m->get_opcode() != websocketpp::frame::opcode::text)
      return bad(c, "binary client messages (client publishing) are not supported by this server");
    const json j = json::parse(m->get_payload(), nullptr, false);
    if (j.is_discarded() || !j.is_object()) return bad(c, "malformed message: not a JSON object");
    const auto op = j.find("op");
    if (op == j.end() || !op->is_string()) return bad(c, "malformed message: no string 'op'");
    const std::string name = *op;
    if (name == "subscribe") return subscribe(c, j.value("subscriptions", json()));
    if (name == "unsubscribe") return unsubscribe(c, j.value("subscriptionIds", json()));
    bad(c, "unsupported operation '" + name + "' (this server offers subscribe and unsubscribe)");
  }

  // Connections still in their handshake, counted now (closed ones drop out as asio frees them).
  size_t pendingNow() {
    pending_conns.erase(std::remove_if(pending_conns.begin(), pending_conns.end(), [this](const Hdl& h) {
      websocketpp::lib::error_code ec;
      const WsServer::connection_ptr con = ws.get_con_from_hdl(h, ec);
      return ec || con->get_state() != websocketpp::session::state::connecting || clients.count(h);
    }), pending_conns.end());
    return pending_conns.size();
  }

  void forget(Hdl h) {
    pending_conns.erase(std::remove_if(pending_conns.begin(), pending_conns.end(),
                                       [&h](const Hdl& p) { return !p.owner_before(h) && !h.owner_before(p); }),
                        pending_conns.end());
  }

  // Our own accept loop (websocketpp's re-accepts at once after an error: with no file
  // descriptor left that spins a core). Every accepted connection counts against max_pending
  // until its handshake is done; over it, the connection is closed before reading a byte.
  void acceptNext() {
    websocketpp::lib::error_code ec;
    WsServer::connection_ptr con = ws.get_connection();
    if (!con) return pauseAccept("cannot create a connection");
    ws.async_accept(websocketpp::lib::static_pointer_cast<WsServer::transport_con_type>(con),
                    [this, con](const websocketpp::lib::error_code& e) { onAccept(con, e); }, ec);
    if (ec) {
      con->terminate(websocketpp::lib::error_code());
      if (running) pauseAccept(ec.message());
    }
  }

  void onAccept(WsServer::connection_ptr con, const websocketpp::lib::error_code& ec) {
    if (ec) {
      con->terminate(ec);
      if (ec == websocketpp::error::operation_canceled || !running) return;  // stop_listening
      return pauseAccept(ec.message());
    }
    if (pendingNow() >= size_t(cfg.max_pending)) {
      count([](ServerStats& s) { ++s.refused_pending; });
      if (!warned_pending) spdlog::warn("live view: {} connections in their handshake (polylocd.live.max_pending): closing new ones at once", cfg.max_pending);
      warned_pending = true;
      con->terminate(websocketpp::lib::error_code());
    } else {
      warned_pending = false;
      pending_conns.push_back(con->get_handle());
      con->start();
    }
    acceptNext();
  }

  void pauseAccept(const std::string& why) {
    count([](ServerStats& s) { ++s.accept_errors; });
    if (!warned_accept) spdlog::warn("live view: accept failed: {}; retrying every 0.2 s", why);
    warned_accept = true;
    accept_pause->expires_after(std::chrono::milliseconds(200));
    accept_pause->async_wait([this](const asio::error_code& e) {
      if (!e && running) acceptNext();
    });
  }

  bool validate(Hdl h) {
    forget(h);
    warned_accept = false;
    WsServer::connection_ptr con = ws.get_con_from_hdl(h);
    const auto& asked = con->get_requested_subprotocols();
    const bool ours = std::find(asked.begin(), asked.end(), kSubprotocol) != asked.end();
    if (!ours || int(clients.size()) >= cfg.max_clients) {
      count([](ServerStats& s) { ++s.refused; });
      con->set_status(ours ? websocketpp::http::status_code::service_unavailable : websocketpp::http::status_code::bad_request);
      con->set_body(ours ? "too many viewers (polylocd.live.max_clients)\n" : std::string("subprotocol ") + kSubprotocol + " required\n");
      spdlog::warn("live view: refused {}: {}", con->get_remote_endpoint(),
                   ours ? "max_clients reached" : "no foxglove.websocket.v1 subprotocol");
      return false;
    }
    con->select_subprotocol(kSubprotocol);
    // Counted here, not at open: two handshakes in flight must not both pass the limit.
    Client& c = clients[h];
    c.hdl = h, c.name = con->get_remote_endpoint();
    return true;
  }

  void onOpen(Hdl h) {
    Client& c = clients[h];
    count([&](ServerStats& s) { ++s.connections, s.clients = clients.size(); });
    spdlog::info("live view: client {} connected ({} now)", c.name, clients.size());
    json info{{"op", "serverInfo"},     {"name", cfg.name},           {"capabilities", json::array()},
              {"supportedEncodings", json::array()}, {"metadata", json::object()}, {"sessionId", std::to_string(::getpid())}};
    websocketpp::lib::error_code ec;
    ws.send(h, info.dump(), websocketpp::frame::opcode::text, ec);
    ws.send(h, advertisement().dump(), websocketpp::frame::opcode::text, ec);
  }

  void onClose(Hdl h) {
    forget(h);
    auto it = clients.find(h);
    if (it == clients.end()) return;
    for (const auto& [sub, ch] : it->second.subs) --subscribers[ch - 1];
    spdlog::info("live view: client {} left", it->second.name);
    clients.erase(it);
    count([&](ServerStats& s) { s.clients = clients.size(); });
  }

  void onHttp(Hdl h) {
    forget(h);
    WsServer::connection_ptr con = ws.get_con_from_hdl(h);
    count([](ServerStats& s) { ++s.http_requests; });
    con->append_header("Connection", "close");  // websocketpp answers one request per connection
    const std::string& path = con->get_resource();
    if ((path == "/" || path == "/index.html") && !cfg.page.empty()) {
      con->set_status(websocketpp::http::status_code::ok);
      con->append_header("Content-Type", "text/html; charset=utf-8");
      con->append_header("Cache-Control", "no-store");
      con->set_body(cfg.page);
    } else {
      con->set_status(websocketpp::http::status_code::not_found);
      con->append_header("Content-Type", "text/plain");
      con->set_body("not found: the live view is at /, Foxglove connects with ws://host:port\n");
    }
  }
};

FoxgloveServer::FoxgloveServer(ServerConfig config) : impl_(std::make_unique<Impl>(std::move(config))) {}
FoxgloveServer::~FoxgloveServer() { stop(); }

uint32_t FoxgloveServer::addChannel(const ChannelSpec& spec) {
  if (impl_->running) throw std::logic_error("FoxgloveServer::addChannel after start");
  impl_->channels.push_back(spec);
  return uint32_t(impl_->channels.size());
}

void FoxgloveServer::start() {
  Impl& m = *impl_;
  m.subscribers = std::make_unique<std::atomic<int>[]>(m.channels.size());
  for (size_t i = 0; i < m.channels.size(); ++i) m.subscribers[i] = 0;
  m.ws.clear_access_channels(websocketpp::log::alevel::all);
  m.ws.clear_error_channels(websocketpp::log::elevel::all);
  m.ws.init_asio();
  m.ws.set_reuse_addr(true);
  m.ws.set_max_message_size(m.cfg.max_client_message);
  m.ws.set_max_http_body_size(m.cfg.max_client_message);
  m.ws.set_open_handshake_timeout(long(m.cfg.handshake_timeout_s * 1000));
  m.ws.set_close_handshake_timeout(1000);
  m.ws.set_validate_handler([&m](Hdl h) { return m.validate(h); });
  m.ws.set_open_handler([&m](Hdl h) { m.onOpen(h); });
  m.ws.set_close_handler([&m](Hdl h) { m.onClose(h); });
  m.ws.set_fail_handler([&m](Hdl h) { m.onClose(h); });  // a handshake that failed after validate
  m.ws.set_message_handler([&m](Hdl h, WsServer::message_ptr msg) { m.onMessage(h, msg); });
  m.ws.set_http_handler([&m](Hdl h) { m.onHttp(h); });
  asio::error_code ec;
  const asio::ip::address addr = asio::ip::make_address(m.cfg.address, ec);
  if (ec) throw std::runtime_error("live view: bad address '" + m.cfg.address + "': " + ec.message());
  websocketpp::lib::error_code wec;
  m.ws.listen(asio::ip::tcp::endpoint(addr, m.cfg.port), wec);
  if (wec)
    throw std::runtime_error("live view: cannot listen on " + m.cfg.address + ":" + std::to_string(m.cfg.port) + ": " + wec.message());
  m.bound_port = m.ws.get_local_endpoint(ec).port();
  if (!addr.is_loopback())  // the protocol has no authentication: whoever reaches the port sees map and poses
    spdlog::warn("live view on {}:{} is open to every host that reaches it (no authentication); 127.0.0.1 keeps it "
                 "on this computer (polylocd.live.address, docs/live.md)", m.cfg.address, m.bound_port);
  m.accept_pause = std::make_unique<asio::steady_timer>(m.ws.get_io_service());
  m.running = true;
  m.acceptNext();
  m.thread = std::thread([&m] {
    try {
      m.ws.run();
    } catch (const std::exception& e) {
      spdlog::error("live view stopped: {}", e.what());  // the daemon goes on without it
    }
  });
}

void FoxgloveServer::stop() {
  Impl& m = *impl_;
  if (!m.running) return;
  m.running = false;
  asio::post(m.ws.get_io_service(), [&m] {
    websocketpp::lib::error_code ec;
    m.ws.stop_listening(ec);
    m.accept_pause->cancel();
    for (auto& [h, c] : m.clients) m.ws.close(h, websocketpp::close::status::going_away, "polylocd stops", ec);
  });
  // Clients that do not answer the close are dropped after the close handshake timeout; then
  // run() returns on its own. stop() after a grace period in case one never does.
  for (int i = 0; i < 40 && stats().clients > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  m.ws.stop();
  if (m.thread.joinable()) m.thread.join();
}

uint16_t FoxgloveServer::port() const { return impl_->bound_port; }

bool FoxgloveServer::subscribed(uint32_t channel) const {
  return impl_->running && channel >= 1 && channel <= impl_->channels.size() &&
         impl_->subscribers[channel - 1].load(std::memory_order_relaxed) > 0;
}

void FoxgloveServer::publish(uint32_t channel, uint64_t stamp_ns, std::shared_ptr<const std::vector<uint8_t>> payload) {
  Impl& m = *impl_;
  if (!m.running || channel < 1 || channel > m.channels.size() || !payload) return;
  if (m.pending.fetch_add(1, std::memory_order_relaxed) >= Impl::kMaxPending) {
    m.pending.fetch_sub(1, std::memory_order_relaxed);
    m.count([](ServerStats& s) { ++s.messages_dropped; });
    return;
  }
  asio::post(m.ws.get_io_service(), [&m, channel, stamp_ns, p = std::move(payload)] {
    m.pending.fetch_sub(1, std::memory_order_relaxed);
    m.fanOut(channel, stamp_ns, p);
  });
}

ServerStats FoxgloveServer::stats() const {
  std::lock_guard l(impl_->stats_m);
  return impl_->st;
}

}  // namespace polyloc::live
