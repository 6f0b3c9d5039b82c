// The server's socket chores: a non-blocking listening socket, and a peer's name for the log.
#pragma once

#include <cstdint>
#include <string>

#include <sys/socket.h>

namespace polyloc::protocol {

// Listens on a numeric IPv4/IPv6 address; bound gets the port (the ephemeral one for port 0).
// Throws std::runtime_error naming address:port and the reason.
int listenOn(const std::string& address, uint16_t port, uint16_t& bound);

std::string peerName(const sockaddr_storage& a, socklen_t len);  // "127.0.0.1:40312", "[::1]:40312"

}  // namespace polyloc::protocol
