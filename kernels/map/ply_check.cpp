#include "ply_check.hpp"

#include <polyloc/map/load.hpp>

#include <fmt/core.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace polyloc::detail {
namespace {

struct Property {
  int size = 0;        // bytes of a scalar, or of a list's items
  int count_size = 0;  // bytes of a list's count; 0 for a scalar
  bool count_signed = false;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

int typeSize(const std::string& type, bool* is_signed = nullptr) {
  static const struct {
    const char* name;
    int size;
    bool is_signed;
  } kTypes[] = {
      {"char", 1, true},  {"int8", 1, true},    {"uchar", 1, false},  {"uint8", 1, false},
      {"short", 2, true}, {"int16", 2, true},   {"ushort", 2, false}, {"uint16", 2, false},
      {"int", 4, true},   {"int32", 4, true},   {"uint", 4, false},   {"uint32", 4, false},
      {"float", 4, true}, {"float32", 4, true}, {"double", 8, true},  {"float64", 8, true}};
  for (const auto& t : kTypes)
    if (type == t.name) {
      if (is_signed) *is_signed = t.is_signed;
      return t.size;
    }
  return 0;
}

class PlyChecker {
 public:
  explicit PlyChecker(const std::string& path) : path_(path) {}

  void run() {
    std::ifstream in(path_, std::ios::binary);
    char magic[3] = {0, 0, 0};
    in.read(magic, 3);
    for (int i = 0; i < 3; ++i)
      if (std::tolower(static_cast<unsigned char>(magic[i])) != "ply"[i]) return;
    in.seekg(0);
    data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    parseHeader();
    if (format_ == "ascii")
      checkAscii();
    else
      checkBinary(format_ == "binary_big_endian");
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw MapError(fmt::format("cannot read map file '{}': corrupt PLY: {}", path_, problem));
  }

  void parseHeader() {
    const size_t end = data_.find("end_header");
    if (end == std::string::npos) fail("header without end_header (truncated file?)");
    size_t body = data_.find('\n', end);
    if (body == std::string::npos) fail("nothing after end_header");
    body_ = body + 1;
    std::istringstream header(data_.substr(0, end));
    std::string line;
    int line_no = 0;
    while (std::getline(header, line)) {
      ++line_no;
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (line_no == 1 || keyword.empty() || keyword == "comment" || keyword == "obj_info")
        continue;
      if (keyword == "format") {
        std::string version;
        words >> format_ >> version;
        if (format_ != "ascii" && format_ != "binary_little_endian" &&
            format_ != "binary_big_endian")
          fail(fmt::format("header line {}: unknown format '{}'", line_no, format_));
      } else if (keyword == "element") {
        Element e;
        std::string count;
        words >> e.name >> count;
        char* rest = nullptr;
        e.count = std::strtoull(count.c_str(), &rest, 10);
        if (e.name.empty() || count.empty() || count[0] == '-' || *rest != '\0')
          fail(fmt::format("header line {}: element needs a name and a count", line_no));
        elements_.push_back(e);
      } else if (keyword == "property") {
        if (elements_.empty())
          fail(fmt::format("header line {}: property before any element", line_no));
        std::string type, item_type, name;
        words >> type;
        Property p;
        if (type == "list") {
          words >> type >> item_type >> name;
          p.count_size = typeSize(type, &p.count_signed);
          p.size = typeSize(item_type);
          if (p.count_size == 0 || p.size == 0 || name.empty() || item_type == "float" ||
              type == "float" || type == "double")
            fail(fmt::format("header line {}: bad list property", line_no));
        } else {
          words >> name;
          p.size = typeSize(type);
          if (p.size == 0 || name.empty())
            fail(fmt::format("header line {}: bad property type '{}'", line_no, type));
        }
        elements_.back().properties.push_back(p);
      } else {
        fail(fmt::format("header line {}: unknown keyword '{}'", line_no, keyword));
      }
    }
    if (format_.empty()) fail("header has no format line");
  }

  void checkAscii() const {
    const char* p = data_.data() + body_;
    const char* const end = data_.data() + data_.size();
    auto token = [&](const Element& e, uint64_t i) {
      while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
      const char* start = p;
      while (p < end && !std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (start == p)
        fail(fmt::format("file ends in {} {} of {} (truncated file?)", e.name, i, e.count));
      const std::string text(start, p);
      char* rest = nullptr;
      const double value = std::strtod(text.c_str(), &rest);
      if (*rest != '\0') fail(fmt::format("'{}' in {} {} is not a number", text, e.name, i));
      return value;
    };
    for (const Element& e : elements_)
      for (uint64_t i = 0; i < e.count; ++i)
        for (const Property& prop : e.properties) {
          const double n = token(e, i);
          if (prop.count_size == 0) continue;
          if (n < 0 || n != std::floor(n))
            fail(fmt::format("bad list length {} in {} {}", n, e.name, i));
          if (n > static_cast<double>(end - p))  // each item takes a character at least
            fail(fmt::format("file ends in {} {} of {} (truncated file?)", e.name, i, e.count));
          for (uint64_t k = 0; k < static_cast<uint64_t>(n); ++k) token(e, i);
        }
  }

  void checkBinary(bool big_endian) const {
    const size_t size = data_.size();
    size_t pos = body_;
    for (const Element& e : elements_) {
      bool has_list = false;
      uint64_t row = 0;
      for (const Property& prop : e.properties) {
        has_list |= prop.count_size != 0;
        row += static_cast<uint64_t>(prop.size);
      }
      if (!has_list) {  // fixed-size rows: one check for the whole element
        if (row != 0 && e.count > (size - pos) / row)
          fail(fmt::format("file ends in element '{}' ({} expected; truncated file?)", e.name,
                           e.count));
        pos += static_cast<size_t>(e.count * row);
        continue;
      }
      for (uint64_t i = 0; i < e.count; ++i)
        for (const Property& prop : e.properties) {
          uint64_t n = 1;
          if (prop.count_size != 0) {
            if (size - pos < static_cast<size_t>(prop.count_size))
              fail(fmt::format("file ends in {} {} of {} (truncated file?)", e.name, i, e.count));
            n = readCount(pos, prop, big_endian);
            pos += static_cast<size_t>(prop.count_size);
          }
          if (n > (size - pos) / static_cast<uint64_t>(prop.size))
            fail(fmt::format("file ends in {} {} of {} (truncated file?)", e.name, i, e.count));
          pos += static_cast<size_t>(n * static_cast<uint64_t>(prop.size));
        }
    }
  }

  uint64_t readCount(size_t pos, const Property& prop, bool big_endian) const {
    unsigned char b[4] = {0, 0, 0, 0};
    std::memcpy(b, data_.data() + pos, static_cast<size_t>(prop.count_size));
    uint64_t v = 0;
    for (int k = 0; k < prop.count_size; ++k) {
      const int byte = big_endian ? k : prop.count_size - 1 - k;
      v = (v << 8) | b[byte];
    }
    const uint64_t sign_bit = uint64_t{1} << (8 * prop.count_size - 1);
    if (prop.count_signed && (v & sign_bit))
      fail(fmt::format("negative list length at byte {}", pos));
    return v;
  }

  const std::string& path_;
  std::string data_;
  size_t body_ = 0;
  std::string format_;
  std::vector<Element> elements_;
};

}  // namespace

void checkPlyStructure(const std::string& path) { PlyChecker(path).run(); }

}  // namespace polyloc::detail
