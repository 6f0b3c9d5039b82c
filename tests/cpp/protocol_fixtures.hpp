// A control server on an ephemeral loopback port with the fake handler, and small helpers for
// the server tests.
#pragma once

#include "protocol_fake_handler.hpp"

#include "protocol/client.hpp"
#include "protocol/server.hpp"

#include <chrono>
#include <functional>
#include <memory>
#include <thread>

namespace polyloc::protocol::fake {

struct TestServer {
  FakeHandler handler;
  Server server;
  explicit TestServer(ServerConfig config = {}) : server(std::move(config), handler) { server.start(); }
  std::unique_ptr<Client> connect(ClientOptions o = {}) {
    return std::make_unique<Client>("127.0.0.1", server.port(), o);
  }
};

// True as soon as pred() is (counters are updated on the server thread).
inline bool eventually(const std::function<bool()>& pred, int timeout_ms = 3000) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (!pred()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

}  // namespace polyloc::protocol::fake
