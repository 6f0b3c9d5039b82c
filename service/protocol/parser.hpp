// Incremental frame parser over a byte stream: push bytes as they arrive, pop complete frames
// or frame errors. It never reads outside what was pushed and it resynchronises by itself:
// - garbage where a frame should start: one BadMagic, then it skips to the next "HELO";
// - a bad CRC: the frame (its size was plausible) is dropped, what follows is judged afresh;
// - a bad or too large size: the magic is dropped and it skips to the next "HELO".
// Bytes skipped while resynchronising give no further error (they belong to the one reported).
// What the server does with an error (reply, count, close) is its policy, not the parser's.
// The events it gives do not depend on how the stream is cut into pushes.
#pragma once

#include "protocol/frame.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace polyloc::protocol {

enum class FrameError {
  None,
  BadMagic,  // bytes where a frame should start that are not "HELO"
  BadSize,   // size field < 16 or not a multiple of 4
  TooLarge,  // size field over max_frame_bytes (reported as soon as the size is read)
  BadCrc,
};
const char* toString(FrameError e);  // "bad_magic", "bad_size", "too_large", "bad_crc"
Status toStatus(FrameError e);       // the FRAME_ERROR reply's status

struct ParseResult {
  enum class Kind { NeedMore, Frame, Error };
  Kind kind = Kind::NeedMore;
  Frame frame;                          // Kind::Frame
  FrameError error = FrameError::None;  // Kind::Error
  uint32_t size = 0;                    // Error: the size field as read (0 for BadMagic)
  uint32_t command = 0;                 // Error: the command word as read (BadCrc only)
  uint64_t offset = 0;                  // stream offset of the frame (or of the garbage)
  std::string message() const;          // "bad CRC in frame at stream byte 40 (...)"
};

class FrameParser {
 public:
  explicit FrameParser(uint32_t max_frame_bytes = kDefaultMaxFrameBytes);

  void push(std::span<const uint8_t> bytes);
  ParseResult next();

  // Bytes held: the start of a frame not yet complete (or 1-3 bytes that may begin a magic).
  size_t buffered() const { return buf_.size() - pos_; }
  // A frame has been started and not completed, or the parser is resynchronising (skipping
  // to the next magic after garbage or a bad size): either way the stream is not at a frame
  // boundary. The server times this state out.
  bool midFrame() const { return buffered() > 0 || resyncing_; }
  uint64_t discarded() const { return discarded_; }  // bytes skipped as garbage or bad frames
  uint32_t maxFrameBytes() const { return max_; }

 private:
  ParseResult fail(FrameError e, uint32_t size, uint32_t command);
  void consume(size_t n);
  bool skipToMagic();  // true: a garbage run began here (report it)

  uint32_t max_;
  std::vector<uint8_t> buf_;
  size_t pos_ = 0;       // first unconsumed byte in buf_
  uint64_t offset_ = 0;  // stream offset of buf_[pos_]
  uint64_t discarded_ = 0;
  bool resyncing_ = false;  // skipping the rest of a reported error: no new BadMagic
};

}  // namespace polyloc::protocol
