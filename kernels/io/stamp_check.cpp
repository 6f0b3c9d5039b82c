#include <polyloc/io/stamp_check.hpp>

#include <fmt/core.h>

namespace polyloc {

int64_t messageStamp(const RecordedMessage& m) {
  int64_t t = 0;
  std::visit([&](const auto& x) {
    if constexpr (requires { x.header.stamp; }) t = msg::toNs(x.header.stamp);
  }, m.message);
  return t ? t : m.log_time_ns;
}

bool isStampedStream(const RecordedMessage& m) {
  return std::holds_alternative<msg::LaserScan>(m.message) || std::holds_alternative<msg::PointCloud2>(m.message) ||
         std::holds_alternative<msg::Image>(m.message) || std::holds_alternative<msg::Odometry>(m.message) ||
         std::holds_alternative<msg::PoseStamped>(m.message);
}

void StampCheck::add(const std::string& topic, int64_t t, uint64_t index) {
  Topic& s = topics_[topic];
  const bool first = s.messages++ == 0;
  const bool zero = t == 0, equal = !zero && !first && t == s.last, back = !zero && !first && t < s.last;
  if (zero || equal || back) {
    if (s.bad() == 0) s.first_index = index, s.first_stamp = t, s.first_previous = s.last;
    s.zero += zero, s.equal += equal, s.backwards += back;
  }
  if (!zero) s.last = t;
}

uint64_t StampCheck::bad() const {
  uint64_t n = 0;
  for (const auto& [name, s] : topics_) n += s.bad();
  return n;
}

std::vector<std::string> StampCheck::warnings() const {
  std::vector<std::string> out;
  for (const auto& [name, s] : topics_) {
    if (s.bad() == 0) continue;
    out.push_back(fmt::format("{}: {} of {} stamps do not increase ({} zero, {} equal to the previous, {} backwards); "
                              "the first is message {}: {:.6f} s after {:.6f} s",
                              name, s.bad(), s.messages, s.zero, s.equal, s.backwards, s.first_index,
                              double(s.first_stamp) * 1e-9, double(s.first_previous) * 1e-9));
  }
  return out;
}

}  // namespace polyloc
