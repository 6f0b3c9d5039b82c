#include "protocol/frame.hpp"

#include <zlib.h>

namespace polyloc::protocol {

uint32_t crc32(std::span<const uint8_t> bytes) {
  // zlib takes uInt lengths; feed large inputs in pieces.
  uLong crc = ::crc32(0L, Z_NULL, 0);
  const uint8_t* p = bytes.data();
  size_t n = bytes.size();
  while (n > 0) {
    const uInt piece = n > (1u << 30) ? (1u << 30) : static_cast<uInt>(n);
    crc = ::crc32(crc, p, piece);
    p += piece, n -= piece;
  }
  return static_cast<uint32_t>(crc);
}

void appendFrame(std::vector<uint8_t>& out, uint32_t command, std::span<const uint32_t> data) {
  const size_t start = out.size();
  const size_t bytes = frameBytes(data.size());
  out.resize(start + bytes);
  uint8_t* p = out.data() + start;
  storeLE32(p, kMagic);
  storeLE32(p + 4, static_cast<uint32_t>(bytes));
  storeLE32(p + 8, command);
  for (size_t i = 0; i < data.size(); ++i) storeLE32(p + 12 + 4 * i, data[i]);
  storeLE32(p + bytes - 4, crc32({p, bytes - 4}));
}

std::vector<uint8_t> encodeFrame(uint32_t command, std::span<const uint32_t> data) {
  std::vector<uint8_t> out;
  appendFrame(out, command, data);
  return out;
}

Frame makeReply(uint32_t request, Status status, std::span<const uint32_t> data) {
  Frame f{replyId(request), {}};
  f.data.reserve(1 + data.size());
  f.data.push_back(static_cast<uint32_t>(static_cast<int32_t>(status)));
  f.data.insert(f.data.end(), data.begin(), data.end());
  return f;
}

Frame frameErrorReply(Status status, uint32_t detail) {
  const uint32_t data[] = {detail};
  return makeReply(cmd::FRAME_ERROR, status, data);
}

Status replyStatus(const Frame& reply) {
  return reply.data.empty() ? Status::BadSize : static_cast<Status>(static_cast<int32_t>(reply.data[0]));
}

std::span<const uint32_t> replyData(const Frame& reply) {
  if (reply.data.empty()) return {};
  return std::span<const uint32_t>(reply.data).subspan(1);
}

}  // namespace polyloc::protocol
