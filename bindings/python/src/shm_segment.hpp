// polyloc.shm's Segment object, shared by shm.cpp (Segment), shm_writer.cpp and shm_reader.cpp.
#pragma once

#include "common.hpp"

#include "shm/segment.hpp"

#include <memory>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

namespace polyloc::py {

// One segment, shared by the Readers and Writers made on it. They keep a pointer to `seg`
// (shm::Reader/Writer follow a re-attach of that object), so it is only ever assigned, under
// the exclusive lock; every read or write holds the shared one.
struct PySegment {
  std::optional<shm::Segment> seg;
  std::shared_mutex mutex;
  bool owner = false;   // made by create(): the context manager stops and unlinks it
  bool closed = false;  // unlinked by __exit__ (the mapping stays: readers still read)

  shm::Segment& get() { return *seg; }
};
using SegmentPtr = std::shared_ptr<PySegment>;

// The index of a channel; KeyError naming the channels there are.
int channelIndex(PySegment& s, const std::string& channel);
// The names of the input channels in channel order (health input[i] belongs to the i-th).
std::vector<std::string> inputNames(PySegment& s);

// The classes on the segment, in the submodule _shm (bindShm calls them after Segment).
void bindShmWriter(pb::module_& m);
void bindShmReader(pb::module_& m);

}  // namespace polyloc::py
