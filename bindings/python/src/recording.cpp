// Recordings (MCAP, ROS 2 bags, CARMEN logs) as Python iterators of (topic, log_time_ns, message).
#include "messages.hpp"

#include <polyloc/io/recording.hpp>

#include <pybind11/stl.h>

#include <fmt/core.h>

#include <memory>
#include <set>

namespace polyloc::py {

namespace recording_impl {  // named, not anonymous: the module is compiled in batches (unity build)

struct PyRecording {
  std::string path;
  std::unique_ptr<RecordingReader> reader;
  std::set<std::string> topics;  // only these; empty: all

  RecordingReader& open() {
    if (!reader) raise(PyExc_ValueError, fmt::format("recording '{}' is closed", path));
    return *reader;
  }
};

pb::object next(PyRecording& r) {
  RecordingReader& reader = r.open();
  RecordedMessage m;
  for (;;) {
    bool more = false;
    {
      pb::gil_scoped_release nogil;  // reading and decoding (zstd, CDR) is C++ work
      more = reader.next(m);
    }
    if (!more) throw pb::stop_iteration();
    if (r.topics.empty() || r.topics.count(m.topic)) break;
  }
  return pb::make_tuple(m.topic, m.log_time_ns, toPython(m.message));
}

}  // namespace recording_impl

void bindRecording(pb::module_& m) {
  using namespace recording_impl;
  pb::class_<PyRecording>(m, "Recording", R"(A recording, read as a stream in log-time order.

    with open_recording("run.mcap") as rec:
        for topic, log_time_ns, message in rec:      # message: a dict (see polyloc.messages)
            ...

Records that cannot be decoded are skipped and counted in stats(); reading goes on.)")
      .def_property_readonly("path", [](const PyRecording& r) { return r.path; })
      .def_property_readonly("format", [](PyRecording& r) { return r.open().format(); }, "'mcap', 'ros2bag' or 'carmen'")
      .def("topics", [](PyRecording& r) {
  using namespace recording_impl;
        pb::list out;
        for (const TopicInfo& t : r.open().topics()) {
          pb::dict d;
          d["name"] = t.name, d["type"] = t.type, d["count"] = t.count, d["first_ns"] = t.first_ns, d["last_ns"] = t.last_ns;
          d["rate_hz"] = t.rateHz();
          out.append(d);
        }
        return out;
      }, "Topics with type, count, first_ns, last_ns, rate_hz.")
      .def("stats", [](PyRecording& r) {
        const ReadStats& s = r.open().stats();
        pb::dict d;
        d["messages"] = s.messages, d["rejected"] = s.rejected, d["warnings"] = s.warnings;
        return d;
      }, "messages delivered, records rejected, and why (first 100 warnings)")
      .def("__iter__", [](pb::object self) { return self; })
      .def("__next__", &next)
      .def("close", [](PyRecording& r) { r.reader.reset(); })
      .def("__enter__", [](pb::object self) { return self; })
      .def("__exit__", [](PyRecording& r, pb::args) { r.reader.reset(); });

  m.def("open_recording", [](const std::string& path, std::vector<std::string> topics) {
    requireExists(path, "open_recording");
    auto r = std::make_unique<PyRecording>();
    r->path = path;
    r->topics = std::set<std::string>(topics.begin(), topics.end());
    pb::gil_scoped_release nogil;
    r->reader = openRecording(path);
    return r;
  }, pb::arg("path"), pb::arg("topics") = std::vector<std::string>{},
        "Open an MCAP file, a ROS 2 bag (directory, metadata.yaml or .db3) or a CARMEN log; only `topics` if given.\n"
        "Raises FileNotFoundError for a missing path, RecordingError (an OSError) for a file of no known format.");
}

}  // namespace polyloc::py
