// Chunk compression for MCAP: zstd (libzstd) and lz4 frames (liblz4), the two the spec names,
// and the CRC-32 that guards chunks and sections (zlib's crc32 is the same polynomial).
#include "mcap_records.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <memory>

namespace polyloc::mcap {
namespace {

// zstd level 3 is libzstd's default: most of the ratio of higher levels at a fraction of the time.
constexpr int kZstdLevel = 3;

void checkDeclared(const char* what, uint64_t declared, uint64_t size) {
  if (declared != size)
    throw FormatError(std::string(what) + " frame declares " + std::to_string(declared) +
                      " bytes, the chunk says " + std::to_string(size));
}

}  // namespace

uint32_t crc32(uint32_t crc, std::span<const uint8_t> bytes) {
  return static_cast<uint32_t>(::crc32_z(crc, bytes.data(), bytes.size()));
}

std::vector<uint8_t> compress(const std::string& compression, std::span<const uint8_t> in) {
  if (compression.empty()) return {in.begin(), in.end()};
  if (compression == "zstd") {
    std::vector<uint8_t> out(ZSTD_compressBound(in.size()));
    size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), kZstdLevel);
    if (ZSTD_isError(n)) throw FormatError(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
    out.resize(n);
    return out;
  }
  if (compression == "lz4") {
    LZ4F_preferences_t prefs = LZ4F_INIT_PREFERENCES;
    prefs.frameInfo.contentSize = in.size();  // lets readers check the size before allocating
    std::vector<uint8_t> out(LZ4F_compressFrameBound(in.size(), &prefs));
    size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), &prefs);
    if (LZ4F_isError(n)) throw FormatError(std::string("lz4 compression failed: ") + LZ4F_getErrorName(n));
    out.resize(n);
    return out;
  }
  throw FormatError("unknown chunk compression \"" + compression + "\" (use zstd, lz4 or none)");
}

std::vector<uint8_t> decompress(const std::string& compression, std::span<const uint8_t> in,
                                uint64_t size) {
  if (size > kMaxChunkBytes)
    throw FormatError("chunk claims " + std::to_string(size) + " uncompressed bytes");
  if (compression.empty()) {
    checkDeclared("uncompressed", in.size(), size);
    return {in.begin(), in.end()};
  }
  if (compression == "zstd") {
    unsigned long long declared = ZSTD_getFrameContentSize(in.data(), in.size());
    if (declared == ZSTD_CONTENTSIZE_ERROR) throw FormatError("zstd: not a zstd frame");
    if (declared != ZSTD_CONTENTSIZE_UNKNOWN) checkDeclared("zstd", declared, size);
    std::vector<uint8_t> out(size);
    size_t n = ZSTD_decompress(out.data(), out.size(), in.data(), in.size());
    if (ZSTD_isError(n)) throw FormatError(std::string("zstd: ") + ZSTD_getErrorName(n));
    checkDeclared("zstd", n, size);
    return out;
  }
  if (compression == "lz4") {
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
      throw FormatError("lz4: cannot create a decompression context");
    std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
        raw, &LZ4F_freeDecompressionContext);
    LZ4F_frameInfo_t info{};
    size_t consumed = in.size();
    size_t r = LZ4F_getFrameInfo(ctx.get(), &info, in.data(), &consumed);
    if (LZ4F_isError(r)) throw FormatError(std::string("lz4: ") + LZ4F_getErrorName(r));
    if (info.contentSize != 0) checkDeclared("lz4", info.contentSize, size);
    std::vector<uint8_t> out(size);
    size_t in_pos = consumed, out_pos = 0;
    while (true) {
      size_t src = in.size() - in_pos, dst = out.size() - out_pos;
      r = LZ4F_decompress(ctx.get(), out.data() + out_pos, &dst, in.data() + in_pos, &src, nullptr);
      if (LZ4F_isError(r)) throw FormatError(std::string("lz4: ") + LZ4F_getErrorName(r));
      in_pos += src;
      out_pos += dst;
      if (r == 0) break;  // frame complete
      if (src == 0 && dst == 0)
        throw FormatError("lz4: frame ends early or holds more than " + std::to_string(size) + " bytes");
    }
    checkDeclared("lz4", out_pos, size);
    return out;
  }
  throw FormatError("unknown chunk compression \"" + compression + "\"");
}

}  // namespace polyloc::mcap
