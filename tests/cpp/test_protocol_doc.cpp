// docs/protocol.md's example session is what the encoder and dispatcher produce: the block
// between its session markers is rebuilt here and must match byte for byte.
#include "protocol_fake_handler.hpp"

#include "protocol/dispatcher.hpp"
#include "protocol/messages.hpp"

#include <gtest/gtest.h>

#include <fmt/core.h>

#include <fstream>
#include <sstream>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_protocol_doc {

using namespace polyloc;
using namespace polyloc::protocol;


// "-> 48 45 4c 4f ..." 16 bytes a line, continuation lines indented.
std::string hexLines(const char* arrow, const std::vector<uint8_t>& bytes) {
  std::string s;
  for (size_t i = 0; i < bytes.size(); ++i) {
    if (i % 16 == 0) s += i == 0 ? std::string(arrow) + " " : "\n   ";
    else s += ' ';
    s += fmt::format("{:02x}", bytes[i]);
  }
  return s + "\n";
}

std::string session() {
  fake::FakeHandler h;
  std::string out;
  const auto step = [&](const std::string& what, uint32_t command, const Words& data) {
    const Frame req{command, data};
    const Frame reply = dispatch(req, h).reply;
    out += "# " + what + "\n" + hexLines("->", encodeFrame(req));
    out += fmt::format("# reply: status {} ({})\n", int32_t(reply.data[0]), toString(replyStatus(reply)));
    out += hexLines("<-", encodeFrame(reply));
  };
  step("PING", cmd::PING, {});
  step("CHECKPROTOCOL, client version 1.1", cmd::CHECKPROTOCOL, {kProtocolVersion});
  step("GETPOSE: x 1.25 m, y -2.5 m, yaw 0.5 rad, stamp 1700000000123456789 ns", cmd::GETPOSE, {});
  step("SETPOSE x 2 m, y 1 m, yaw 90 deg, sigma_xy 0.25 m, sigma_yaw 10 deg", cmd::SETPOSE,
       encodeSeed({2.0, 1.0, deg2rad(90), 0.25, deg2rad(10)}));
  step("GETNUMSCANNERS: 3 (the VRS, front, rear)", cmd::GETNUMSCANNERS, {});
  step("SETCOLLISIONAVOIDANCE 0: VRS publication off", cmd::SETCOLLISIONAVOIDANCE, {0});
  step("GETSCANRADIALSCANNER 5: no such scanner", cmd::GETSCANRADIALSCANNER, {5});
  out += "# 7 bytes of garbage (\"GET /\\r\\n\"): the server answers FRAME_ERROR, bad_magic, detail 0\n";
  out += hexLines("->", {'G', 'E', 'T', ' ', '/', '\r', '\n'});
  out += hexLines("<-", encodeFrame(frameErrorReply(Status::BadMagic)));
  return out;
}

std::string docBlock() {
  std::ifstream f(std::string(POLYLOC_SOURCE_DIR) + "/docs/protocol.md");
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string doc = ss.str();
  const std::string begin = "<!-- session:begin -->\n```\n", end = "```\n<!-- session:end -->";
  const size_t a = doc.find(begin), b = doc.find(end);
  if (a == std::string::npos || b == std::string::npos || b < a) return "(no session block in docs/protocol.md)";
  return doc.substr(a + begin.size(), b - a - begin.size());
}


TEST(ProtocolDoc, ExampleSessionIsWhatTheCodeSends) {
  EXPECT_EQ(docBlock(), session()) << "docs/protocol.md's session block should read:\n" << session();
}

}  // namespace polyloc::t_protocol_doc
