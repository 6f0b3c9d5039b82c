// The topic list a reader builds as it reads (recording.hpp); its own file so that a reader
// (and its fuzzer) needs no other format's code.
#include <polyloc/io/recording.hpp>

#include <algorithm>

namespace polyloc {

void TopicTally::add(const RecordedMessage& m) {
  auto [it, added] = index_.try_emplace(m.topic, topics_.size());
  if (added) topics_.push_back({m.topic, msg::typeName(m.message), 0, m.log_time_ns, m.log_time_ns});
  TopicInfo& t = topics_[it->second];
  ++t.count;
  t.first_ns = std::min(t.first_ns, m.log_time_ns);
  t.last_ns = std::max(t.last_ns, m.log_time_ns);
}

}  // namespace polyloc
