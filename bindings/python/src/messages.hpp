// ROS 2 messages of a recording as Python dicts with numpy arrays (recording.cpp reads them).
#pragma once

#include "common.hpp"

#include <polyloc/io/messages.hpp>

namespace polyloc::py {

// A dict with "type" (the ROS 2 type name), "stamp_ns" and "frame_id" where the message has a
// header, and its fields; arrays for ranges, images (decoded: 32FC1, 16UC1, mono8, ...),
// point clouds (a structured array of the fields) and covariances.
pb::dict toPython(const msg::Message& m);

}  // namespace polyloc::py
