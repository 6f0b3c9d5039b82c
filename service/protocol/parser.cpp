#include "protocol/parser.hpp"

#include <algorithm>
#include <cstring>
#include <string>

namespace polyloc::protocol {
namespace {

constexpr uint8_t kMagicBytes[4] = {'H', 'E', 'L', 'O'};

// The n (<= 4) bytes at p could be the start of a magic.
bool magicPrefix(const uint8_t* p, size_t n) { return std::memcmp(p, kMagicBytes, std::min<size_t>(n, 4)) == 0; }

std::string hex(uint32_t v) {
  static const char* digits = "0123456789abcdef";
  std::string s = "0x00000000";
  for (int i = 0; i < 8; ++i) s[9 - i] = digits[(v >> (4 * i)) & 0xf];
  return s;
}

}  // namespace

const char* toString(FrameError e) {
  switch (e) {
    case FrameError::None: return "none";
    case FrameError::BadMagic: return "bad_magic";
    case FrameError::BadSize: return "bad_size";
    case FrameError::TooLarge: return "too_large";
    case FrameError::BadCrc: return "bad_crc";
  }
  return "unknown";
}

Status toStatus(FrameError e) {
  switch (e) {
    case FrameError::BadMagic: return Status::BadMagic;
    case FrameError::BadSize: return Status::BadFrameSize;
    case FrameError::TooLarge: return Status::FrameTooLarge;
    case FrameError::BadCrc: return Status::BadCrc;
    case FrameError::None: break;
  }
  return Status::Ok;
}

std::string ParseResult::message() const {
  const std::string at = " at stream byte " + std::to_string(offset);
  switch (error) {
    case FrameError::BadMagic: return "bytes that are not a frame start (magic \"HELO\")" + at + ", skipped";
    case FrameError::BadSize:
      return "frame" + at + ": size field " + std::to_string(size) + " is not a multiple of 4 of at least 16";
    case FrameError::TooLarge: return "frame" + at + ": size field " + std::to_string(size) + " is over the limit";
    case FrameError::BadCrc:
      return "frame" + at + " (command " + hex(command) + ", " + std::to_string(size) + " bytes): CRC-32 mismatch";
    case FrameError::None: break;
  }
  return kind == Kind::Frame ? "frame" + at : "no complete frame yet";
}

FrameParser::FrameParser(uint32_t max_frame_bytes) : max_(std::max(max_frame_bytes, kMinFrameBytes)) {}

void FrameParser::push(std::span<const uint8_t> bytes) {
  // Compact before growing, so the buffer holds at most one frame plus one push.
  if (pos_ > 0 && pos_ >= buf_.size() / 2) {
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(pos_));
    pos_ = 0;
  }
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void FrameParser::consume(size_t n) {
  pos_ += n;
  offset_ += n;
  if (pos_ == buf_.size()) buf_.clear(), pos_ = 0;
}

ParseResult FrameParser::fail(FrameError e, uint32_t size, uint32_t command) {
  ParseResult r;
  r.kind = ParseResult::Kind::Error;
  r.error = e, r.size = size, r.command = command, r.offset = offset_;
  if (e == FrameError::BadCrc) {
    // The size was plausible and the whole frame is here: drop it, judge what follows afresh.
    discarded_ += size;
    consume(size);
    return r;
  }
  // The size cannot be trusted: drop the magic (it has no self-overlap, so no other frame can
  // start inside it) and skip silently to the next magic.
  discarded_ += 4;
  consume(4);
  resyncing_ = true;
  return r;
}

bool FrameParser::skipToMagic() {
  const size_t end = buf_.size();
  size_t i = pos_ + 1;
  for (; i < end; ++i) {
    const void* h = std::memchr(buf_.data() + i, 'H', end - i);
    if (!h) {
      i = end;
      break;
    }
    i = static_cast<size_t>(static_cast<const uint8_t*>(h) - buf_.data());
    if (magicPrefix(buf_.data() + i, end - i)) break;
  }
  const bool began = !resyncing_;
  discarded_ += i - pos_;
  consume(i - pos_);
  resyncing_ = true;
  return began;
}

ParseResult FrameParser::next() {
  for (;;) {
    const size_t avail = buffered();
    if (avail == 0) return {};
    const uint8_t* p = buf_.data() + pos_;
    if (!magicPrefix(p, avail)) {
      const uint64_t at = offset_;
      if (skipToMagic()) {
        ParseResult r;
        r.kind = ParseResult::Kind::Error, r.error = FrameError::BadMagic, r.offset = at;
        return r;
      }
      continue;
    }
    if (avail < 8) return {};  // a magic (or its start) and no size yet
    resyncing_ = false;        // a full magic: whatever follows is judged afresh
    const uint32_t size = loadLE32(p + 4);
    if (size < kMinFrameBytes || size % 4 != 0) return fail(FrameError::BadSize, size, 0);
    if (size > max_) return fail(FrameError::TooLarge, size, 0);
    if (avail < size) return {};
    const uint32_t command = loadLE32(p + 8);
    if (crc32({p, size - 4}) != loadLE32(p + size - 4)) return fail(FrameError::BadCrc, size, command);
    ParseResult r;
    r.kind = ParseResult::Kind::Frame;
    r.offset = offset_;
    r.frame.command = command;
    r.frame.data.resize((size - kMinFrameBytes) / 4);
    for (size_t k = 0; k < r.frame.data.size(); ++k) r.frame.data[k] = loadLE32(p + 12 + 4 * k);
    consume(size);
    return r;
  }
}

}  // namespace polyloc::protocol
