// ROS messages into polylocd's input channels, as a robot's drivers would write them: a topic
// goes to the channel of its sensor (/scan/<s> or /<s> -> scan/<s>; /depth/<s>/image with its
// /depth/<s>/amplitude of the same stamp -> depth/<s>; nav_msgs/Odometry -> odom; CARMEN's
// /front_laser and /robot_laser -> the first scan channel, /rear_laser -> the second). Used by
// `polyloc play` and the tests. Frames that do not fit a channel are still written when they
// can be held, so that polylocd rejects and counts them as it would a driver's.
#pragma once

#include "shm/channel.hpp"

#include <polyloc/io/messages.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace polyloc::pipeline {

class MessageFeed {
 public:
  explicit MessageFeed(shm::Segment& seg);

  enum class Sent { Frame, Pending, NoChannel, NotInput };
  // stamp_shift_ns is added to every stamp (onto the wall clock, for playback).
  Sent send(const std::string& topic, int64_t log_time_ns, const msg::Message& m, int64_t stamp_shift_ns = 0);
  void flush();  // depth images still waiting for their amplitude go out without it

  const std::map<std::string, uint64_t>& perChannel() const { return per_channel_; }
  uint64_t sent() const { return sent_; }

 private:
  struct DepthPending {
    int channel = -1;
    int64_t stamp = 0;
    std::vector<float> depth;
    bool pending = false;
  };
  shm::Writer& writer(int channel);
  void sendDepth(DepthPending& d, const std::vector<float>* amplitude);
  Sent counted(int channel);

  shm::Segment& seg_;
  std::map<int, std::unique_ptr<shm::Writer>> writers_;
  std::vector<int> scan_channels_;
  std::map<std::string, DepthPending> depth_;  // by camera name
  std::map<std::string, uint64_t> per_channel_;
  uint64_t sent_ = 0;
};

}  // namespace polyloc::pipeline
