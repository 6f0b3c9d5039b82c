// polyloc.shm: the shared-memory client (service/shm, docs/interface.md) over numpy arrays: attach
// to a polylocd instance's segment (or create one, for tests and simulations), write its input
// channels, read its outputs as dicts. Every frame of every kind can be written and read, so a
// Python program can stand in for either side. ShmError codes become Python exceptions that
// derive from the builtin a caller would catch (SegmentNotFoundError is a FileNotFoundError).
// Here: the submodule, its exceptions and Segment; Writer, Reader and the dicts have files of their own.
#include "shm_dicts.hpp"
#include "shm_segment.hpp"

#include "shm/atomic.hpp"
#include "shm/segment.hpp"

#include <polyloc_shm.h>

#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

namespace polyloc::py {

namespace shm_impl {  // named, not anonymous: the module is compiled in batches (unity build)

using shm::ShmError;
using Errc = ShmError::Errc;

// The exception classes of polyloc.shm (created in bindShm, alive as long as the module).
PyObject* exc_base = nullptr;        // ShmError(RuntimeError)
PyObject* exc_not_found = nullptr;   // SegmentNotFoundError(ShmError, FileNotFoundError)
PyObject* exc_abi = nullptr;         // AbiError(ShmError)
PyObject* exc_not_ready = nullptr;   // NotReadyError(ShmError)
PyObject* exc_busy = nullptr;        // BusyError(ShmError)
PyObject* exc_argument = nullptr;    // ShmValueError(ShmError, ValueError)

PyObject* newException(pb::module_& m, const char* name, const char* doc, std::vector<PyObject*> bases) {
  pb::tuple b(bases.size());
  for (size_t i = 0; i < bases.size(); ++i) b[i] = pb::reinterpret_borrow<pb::object>(bases[i]);
  const std::string full = std::string("polyloc.shm.") + name;
  PyObject* e = PyErr_NewExceptionWithDoc(full.c_str(), doc, b.ptr(), nullptr);
  if (!e) throw pb::error_already_set();
  m.attr(name) = pb::reinterpret_borrow<pb::object>(e);  // the module keeps a reference too
  return e;
}

PyObject* exceptionFor(Errc c) {
  switch (c) {
    case Errc::NotFound: return exc_not_found;
    case Errc::Abi: return exc_abi;
    case Errc::NotReady: return exc_not_ready;
    case Errc::Busy: return exc_busy;
    case Errc::Argument: return exc_argument;
    default: return exc_base;
  }
}

const char* stateName(uint32_t s) {
  switch (s) {
    case POLYLOC_STATE_INITIALISING: return "initialising";
    case POLYLOC_STATE_READY: return "ready";
    case POLYLOC_STATE_STOPPED: return "stopped";
    default: return "unknown";
  }
}

}  // namespace shm_impl

int channelIndex(PySegment& s, const std::string& channel) {
  using namespace shm_impl;
  const int ch = s.get().find(channel);
  if (ch < 0) {
    std::string names;
    for (int i = 0; i < s.get().channelCount(); ++i) names += (i ? ", " : "") + channelName(s.get().channel(i));
    raise(PyExc_KeyError, "segment " + s.get().name() + " has no channel '" + channel + "' (it has " + names + ")");
  }
  return ch;
}

std::vector<std::string> inputNames(PySegment& s) {
  using namespace shm_impl;
  std::vector<std::string> out;
  for (int i = 0; i < s.get().channelCount(); ++i)
    if (s.get().channel(i).direction == POLYLOC_DIR_INPUT) out.push_back(channelName(s.get().channel(i)));
  return out;
}

void bindShm(pb::module_& parent) {
  using namespace shm_impl;
  pb::module_ m = parent.def_submodule("_shm", R"(The shared-memory client: polylocd's segment, its input and output channels.

    seg = shm.Segment.attach("lab")                    # polylocd --instance lab
    pose = shm.Reader(seg, "pose", start="newest")
    odom = shm.Writer(seg, "odom")
    odom.write_odometry(stamp_ns, odom_T_base)
    if pose.wait(0.1): print(pose.next())              # dict: stamp_ns, pose, covariance, status, ...

docs/interface.md is the layout; docs/python.md has an example.)");

  exc_base = newException(m, "ShmError", "A shared-memory failure: the message names the segment and what was wrong.",
                          {PyExc_RuntimeError});
  exc_not_found = newException(m, "SegmentNotFoundError", "No segment of that name (is polylocd running for the instance?).",
                               {exc_base, PyExc_FileNotFoundError});
  exc_abi = newException(m, "AbiError", "The segment speaks another POLYLOC_SHM_ABI_VERSION (both versions in the message).",
                         {exc_base});
  exc_not_ready = newException(m, "NotReadyError", "The segment is being created (polylocd is starting): retry.", {exc_base});
  exc_busy = newException(m, "BusyError", "A live process holds the segment or the channel's writer role.", {exc_base});
  exc_argument = newException(m, "ShmValueError", "A bad instance name or channel spec.", {exc_base, PyExc_ValueError});
  pb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ShmError& e) {
      PyErr_SetString(exceptionFor(e.code()), e.what());
    }
  });
  m.attr("ABI_VERSION") = POLYLOC_SHM_ABI_VERSION;

  pb::class_<PySegment, SegmentPtr>(m, "Segment", R"(One polylocd instance's segment /dev/shm/polyloc.<instance>.

    seg = Segment.attach("lab")              # SegmentNotFoundError, AbiError, NotReadyError, ShmError
    seg.channels()                           # [{'name': 'scan/s300_front_left', 'kind': 'ranges', ...}, ...]
    if seg.stale(): seg.reattach()           # polylocd restarted or stopped; readers and writers follow

    with Segment.create("sim", [{"name": "pose", "kind": "pose"}, ...]) as seg:   # tests, simulations
        ...                                  # on exit: state stopped and the name unlinked)")
      .def_static("attach", [](const std::string& instance) {
        auto s = std::make_shared<PySegment>();
        {
          pb::gil_scoped_release nogil;
          s->seg = shm::Segment::attach(instance);
        }
        return s;
      }, pb::arg("instance"), "Maps an existing segment; checks magic, ABI version, sizes and state.")
      .def_static("create", [](const std::string& instance, const pb::iterable& channels, bool ready) {
        std::vector<shm::ChannelSpec> specs;
        for (auto c : channels) specs.push_back(toSpec(c));
        auto s = std::make_shared<PySegment>();
        s->owner = true;
        pb::gil_scoped_release nogil;
        s->seg = shm::Segment::create(instance, specs);
        if (ready) s->seg->ready();
        return s;
      }, pb::arg("instance"), pb::arg("channels"), pb::arg("ready") = true,
        R"(Creates (or replaces: generation + 1) the segment with these channels, owned by this process.

channels: dicts with name and kind ('ranges', 'depth', 'odometry', 'pose', 'vrs', 'tracks', 'health'),
optional direction ('input'/'output'; default by kind), slots (16), count (beams, VRS segments),
width and height (depth), sensor (rig index, -1), payload_max; or daemon_channels(config).
ready=False leaves it initialising (clients cannot attach) until ready().)")
      .def_static("unlink", [](const std::string& instance) {
  using namespace shm_impl;
        pb::gil_scoped_release nogil;
        shm::Segment::unlink(instance);
      }, pb::arg("instance"), "Removes the name (mapped segments stay valid).")
      .def_property_readonly("instance", [](PySegment& s) { return s.get().instance(); })
      .def_property_readonly("name", [](PySegment& s) { return s.get().name(); }, "/polyloc.<instance>")
      .def_property_readonly("generation", [](PySegment& s) { return s.get().generation(); }, "as attached")
      .def_property_readonly("state", [](PySegment& s) {
        return stateName(shm::atomic::loadAcquire(&s.get().header().state));
      }, "'initialising', 'ready' or 'stopped' (now)")
      .def_property_readonly("owner_pid", [](PySegment& s) { return s.get().header().owner_pid; })
      .def_property_readonly("created_ns", [](PySegment& s) { return s.get().header().created_ns; })
      .def_property_readonly("size", [](PySegment& s) { return s.get().size(); }, "bytes")
      .def_property_readonly("owner", [](PySegment& s) { return s.owner; }, "made by create() in this process")
      .def("stale", [](PySegment& s) {
        pb::gil_scoped_release nogil;
        std::shared_lock lock(s.mutex);
        return s.get().stale();
      }, "True when polylocd restarted (another generation), stopped or died: reattach(). A few system calls.")
      .def("reattach", [](PySegment& s) {
        pb::gil_scoped_release nogil;
        std::unique_lock lock(s.mutex);
        s.seg = shm::Segment::attach(s.get().instance());
        s.owner = false;
      }, "Attaches again by instance name, in place: Readers and Writers on this Segment follow on their next call.")
      .def("ready", [](PySegment& s) { s.get().ready(); }, "State ready (the owner).")
      .def("stop", [](PySegment& s) { s.get().stop(); }, "State stopped (the owner): clients see it stale.")
      .def("channels", [](PySegment& s) {
        std::shared_lock lock(s.mutex);
        pb::list out;
        for (int i = 0; i < s.get().channelCount(); ++i) out.append(channelDict(s.get().channel(i)));
        return out;
      }, "The channel table: dicts of name, kind, direction, count, width, height, sensor, slots, payload_max.")
      .def("find", [](PySegment& s, const std::string& name) { return s.get().find(name); }, pb::arg("channel"),
           "Index of a channel, or -1.")
      .def("__contains__", [](PySegment& s, const std::string& name) { return s.get().find(name) >= 0; })
      .def("__enter__", [](SegmentPtr s) { return s; })
      .def("__exit__", [](PySegment& s, pb::args) {
        if (s.owner && !s.closed) {
          s.get().stop();
          shm::Segment::unlink(s.get().instance());
          s.closed = true;
        }
        return false;
      }, "For a segment made by create(): state stopped and the name unlinked.")
      .def("__repr__", [](PySegment& s) {
        return "<polyloc.shm.Segment " + s.get().name() + " generation " + std::to_string(s.get().generation()) + ", " +
               std::to_string(s.get().channelCount()) + " channels>";
      });

  bindShmWriter(m);
  bindShmReader(m);
}

}  // namespace polyloc::py
