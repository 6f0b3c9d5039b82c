// Stamps that do not increase, per topic: zero, equal to the topic's previous one (a log written
// with too few digits: csail's `1.13486e+09`), or going backwards. Counted, with the first place,
// so that `polyloc info` and `localize` can say what is wrong with a log's time and where, and
// suggest --restamp (io/restamp.hpp).
//
//   StampCheck check;
//   for each message: check.add(m.topic, stamp, index);
//   for (auto& w : check.warnings()) ...
#pragma once

#include <polyloc/io/recording.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace polyloc {

// The stamp consumers use: the message's header stamp, else (no header, or a zero stamp) its
// log time.
int64_t messageStamp(const RecordedMessage& m);

// Whether the message's topic is a stream whose stamps must increase: scans, clouds, images,
// odometry, poses. Track arrays (one per scanner frame), camera infos and static transforms may
// repeat a stamp.
bool isStampedStream(const RecordedMessage& m);

class StampCheck {
 public:
  struct Topic {
    uint64_t messages = 0;
    uint64_t zero = 0, equal = 0, backwards = 0;  // a stamp counts once: zero first, then equal, then backwards
    uint64_t first_index = 0;    // the message (index in the recording) of the first problem
    int64_t first_stamp = 0, first_previous = 0;
    int64_t last = 0;            // the topic's previous non-zero stamp
    uint64_t bad() const { return zero + equal + backwards; }
  };

  void add(const std::string& topic, int64_t stamp_ns, uint64_t index);
  const std::map<std::string, Topic>& topics() const { return topics_; }
  uint64_t bad() const;  // over all topics
  // One line per topic with bad stamps, e.g. "/odom: 440 of 7814 stamps do not increase (440
  // zero, 0 equal to the previous, 0 backwards); the first is message 139: 0.000000 s after
  // 21.019900 s".
  std::vector<std::string> warnings() const;

 private:
  std::map<std::string, Topic> topics_;
};

}  // namespace polyloc
