// One request frame in, one reply frame out: checks each command's data size and arguments,
// calls the handler, encodes its answer (messages.hpp). No sockets and no logging here, so the
// server, the tests and the fuzzer drive the same code.
#pragma once

#include "protocol/frame.hpp"
#include "protocol/handler.hpp"

#include <string>

namespace polyloc::protocol {

struct Dispatched {
  Frame reply;
  std::string failure;  // the handler threw: what it said (the reply's status is Internal)
};

Dispatched dispatch(const Frame& request, ControlHandler& handler);

}  // namespace polyloc::protocol
