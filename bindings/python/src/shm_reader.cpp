// polyloc.shm.Reader: one channel read at the reader's own pace, frames as dicts (shm_dicts.cpp);
// waits and copies run with the GIL released.
#include "shm_dicts.hpp"
#include "shm_segment.hpp"

#include "shm/channel.hpp"

#include <polyloc_shm.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

namespace polyloc::py {

namespace shm_reader_impl {  // named, not anonymous: the module is compiled in batches (unity build)

struct PyReader {
  SegmentPtr seg;
  std::unique_ptr<shm::Reader> r;
  std::mutex mutex;
  polyloc_channel_desc desc{};

  template <class F> pb::object read(F&& f) {
    std::vector<uint8_t> buf;
    std::optional<shm::FrameInfo> info;
    std::vector<std::string> inputs;
    polyloc_channel_desc now{};
    {
      pb::gil_scoped_release nogil;
      std::shared_lock lock(seg->mutex);
      Guard g(mutex);
      info = f(*r, buf);
      now = r->channel();  // after a re-attach: the channel as it is in the new segment
      if (info && now.kind == POLYLOC_KIND_HEALTH) inputs = inputNames(*seg);
    }
    if (!info) return pb::none();
    return frameDict(*info, buf, now, inputs);
  }
};

}  // namespace shm_reader_impl

void bindShmReader(pb::module_& m) {
  using namespace shm_reader_impl;
  pb::class_<PyReader>(m, "Reader", R"(A reader of one channel, at its own pace: it never disturbs the writer or other readers.

    r = Reader(seg, "pose", start="next")    # "next": frames after now; "newest": the last one too; "oldest": the ring
    while r.wait(0.1):                       # seconds; the GIL is released meanwhile
        frame = r.next()                     # a dict, or None when nothing is new

A reader that falls behind by more than the ring's slots skips to the newest frame and counts
the frames lost in overruns.)")
      .def(pb::init([](SegmentPtr seg, const std::string& channel, const std::string& start) {
  using namespace shm_reader_impl;
             shm::Reader::Start s = shm::Reader::Start::Next;
             if (start == "newest") s = shm::Reader::Start::Newest;
             else if (start == "oldest") s = shm::Reader::Start::Oldest;
             else if (start != "next") raise(PyExc_ValueError, "start '" + start + "': next, newest or oldest");
             auto r = std::make_unique<PyReader>();
             r->seg = seg;
             const int ch = channelIndex(*seg, channel);
             std::shared_lock lock(seg->mutex);
             r->r = std::make_unique<shm::Reader>(seg->get(), ch, s);
             r->desc = r->r->channel();
             return r;
           }),
           pb::arg("segment"), pb::arg("channel"), pb::arg("start") = "next")
      .def_property_readonly("channel", [](PyReader& r) { return channelDict(r.desc); })
      .def("next", [](PyReader& r) {
        return r.read([](shm::Reader& rd, std::vector<uint8_t>& b) { return rd.next(b); });
      }, "The oldest unread frame as a dict, or None. After an overrun: the newest (and overruns grows).")
      .def("newest", [](PyReader& r) {
        return r.read([](shm::Reader& rd, std::vector<uint8_t>& b) { return rd.newest(b); });
      }, "The newest frame (skipping older unread ones, not an overrun), or None if none was ever published.")
      .def("drain", [](PyReader& r) {
        pb::list out;
        for (;;) {
          pb::object f = r.read([](shm::Reader& rd, std::vector<uint8_t>& b) { return rd.next(b); });
          if (f.is_none()) return out;
          out.append(f);
        }
      }, "Every unread frame, oldest first (a list of dicts).")
      .def("wait", [](PyReader& r, double timeout_s, double spin_s) {
        const int64_t timeout = timeout_s < 0 ? -1 : static_cast<int64_t>(timeout_s * 1e9);
        const auto spin = static_cast<int64_t>(std::max(0.0, spin_s) * 1e9);
        pb::gil_scoped_release nogil;
        std::shared_lock lock(r.seg->mutex);
        Guard g(r.mutex);
        return r.r->wait(timeout, spin);
      }, pb::arg("timeout_s"), pb::arg("spin_s") = 0.0,
           "Blocks (GIL released) until an unread frame is there or timeout_s passed (< 0: no limit, 0: poll); True when one is.")
      .def_property_readonly("available", [](PyReader& r) {
        pb::gil_scoped_release nogil;
        std::shared_lock lock(r.seg->mutex);
        Guard g(r.mutex);
        return r.r->available();
      }, "published frames not yet read (at most the ring's slots)")
      .def_property_readonly("overruns", [](PyReader& r) {
        pb::gil_scoped_release nogil;
        Guard g(r.mutex);
        return r.r->overruns();
      }, "frames lost because the writer lapped this reader")
      .def_property_readonly("torn", [](PyReader& r) {
        pb::gil_scoped_release nogil;
        Guard g(r.mutex);
        return r.r->torn();
      }, "reads retried because the writer overwrote the slot meanwhile");
}

}  // namespace polyloc::py
