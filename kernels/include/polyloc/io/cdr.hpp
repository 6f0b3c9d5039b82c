// CDR (XCDR1, little endian, with the 4-byte encapsulation header) encoding of the messages in
// messages.hpp, as ROS 2 (rmw_fastrtps) puts them on the wire and in bags, via Fast-CDR.
// Also the ros2msg schema texts that MCAP and bags carry.
#pragma once

#include <polyloc/io/error.hpp>
#include <polyloc/io/messages.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace polyloc::msg {

std::vector<uint8_t> encodeCdr(const Message& m);
// Throws polyloc::IoError for an unknown type or malformed bytes, saying which.
Message decodeCdr(const std::string& type_name, std::span<const uint8_t> bytes);
// The ros2msg definition of a type with its dependencies appended, separated the way ROS 2
// tooling (rosbag2, foxglove) expects: "=====...\nMSG: pkg/Type\n<definition>".
const std::string& ros2msgSchema(const std::string& type_name);

}  // namespace polyloc::msg
