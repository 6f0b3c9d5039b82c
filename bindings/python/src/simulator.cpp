// The simulator: scenarios, a run to a recording (MCAP or ROS 2 bag) and/or through Python
// callbacks. The run releases the GIL; each callback takes it back for the Python call, and an
// exception raised in a callback ends the run and reaches the caller of run().
#include "common.hpp"

#include <polyloc/io/recording.hpp>
#include <polyloc/sim/noise.hpp>
#include <polyloc/sim/simulator.hpp>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <memory>
#include <mutex>

namespace polyloc::py {

namespace simulator_impl {  // named, not anonymous: the module is compiled in batches (unity build)

template <class T>
pb::array_t<T> frameView(pb::object self, const std::vector<T> SimFrame::*field) {
  const std::vector<T>& v = self.cast<const SimFrame&>().*field;
  return view<T>(v.data(), {static_cast<pb::ssize_t>(v.size())}, self);
}

struct PySimulator {
  std::unique_ptr<Simulator> sim;
  std::mutex running;
};

std::unique_ptr<RecordingWriter> writerFor(const std::string& out) {
  if (out.empty()) return std::make_unique<NullRecordingWriter>();
  return out.ends_with(".mcap") ? createMcap(out) : createRos2Bag(out);
}

pb::dict runSimulation(PySimulator& s, const std::string& out, const pb::object& on_frame, const pb::object& on_tick,
                       const pb::object& on_progress) {
  std::unique_lock lock(s.running, std::try_to_lock);
  if (!lock) raise(PyExc_RuntimeError, "Simulator.run: this simulator is already running (a callback called run?)");
  SimHooks hooks;
  if (!on_frame.is_none())
    hooks.on_frame = [&](const SimFrame& f) {
      pb::gil_scoped_acquire gil;
      on_frame(pb::cast(f, pb::return_value_policy::copy));
    };
  if (!on_tick.is_none())
    hooks.on_tick = [&](int64_t stamp, const Pose& gt, const Pose& odom) {
      pb::gil_scoped_acquire gil;
      on_tick(stamp, pb::cast(gt, pb::return_value_policy::copy), pb::cast(odom, pb::return_value_policy::copy));
    };
  if (!on_progress.is_none())
    hooks.on_progress = [&](double f) {
      pb::gil_scoped_acquire gil;
      on_progress(f);
    };
  SimSummary summary;
  {
    pb::gil_scoped_release nogil;
    std::unique_ptr<RecordingWriter> writer = writerFor(out);
    summary = s.sim->run(*writer, hooks);
    writer->close();
  }
  pb::dict d, topics;
  for (const auto& [topic, count] : summary.topics) topics[pb::str(topic)] = count;
  d["sim_duration_s"] = summary.sim_duration_s, d["messages"] = summary.messages, d["topics"] = topics;
  d["floor_misses"] = summary.floor_misses, d["chairs_moved"] = summary.chairs_moved;
  if (!out.empty()) d["output"] = out;
  return d;
}

}  // namespace simulator_impl

void bindSimulator(pb::module_& m) {
  using namespace simulator_impl;
  pb::class_<Scenario>(m, "Scenario", "A simulated run (maps/scenarios/*.yaml): config (map, robot, rig), route, people, noise, seed.")
      .def_readonly("file", &Scenario::file)
      .def_readwrite("config", &Scenario::config)
      .def_readwrite("seed", &Scenario::seed)
      .def_readwrite("start_time_ns", &Scenario::start_time_ns, "stamp of t = 0")
      .def_readwrite("duration", &Scenario::duration, "s; 0: the route's duration + 1 s")
      .def_property("noise", [](const Scenario& s) { return s.noise.enabled; }, [](Scenario& s, bool v) { s.noise.enabled = v; },
                    "False: exact ranges, no artefacts, exact odometry")
      .def_property_readonly("num_people", [](const Scenario& s) { return s.people.size(); });
  m.def("load_scenario", [](const std::string& path, std::optional<double> duration, std::optional<uint64_t> seed) {
    requireExists(path, "load_scenario");
    Scenario s = loadScenario(path);
    if (duration) {
      if (!(*duration > 0)) raise(PyExc_ValueError, fmt::format("load_scenario: duration must be positive, got {}", *duration));
      s.duration = *duration;
    }
    if (seed) s.seed = *seed;
    return s;
  }, pb::arg("path"), pb::arg("duration") = pb::none(), pb::arg("seed") = pb::none(),
        "Read a scenario, optionally shortened to `duration` s or with another seed. ConfigError names file, line and key.");

  pb::class_<SimFrame>(m, "SimFrame", R"(One simulated sensor frame (Simulator.run's on_frame).

exact: ideal range per beam (+inf: miss); measured: what the sensor reports (NaN invalid, +inf
miss; ToF cameras: range along the ray, not depth), which is what Localizer.add_scan takes;
artefacts: ARTEFACT_BITS per beam; label: label id in Simulator.map of the exact hit.)")
      .def_readonly("sensor", &SimFrame::sensor, "rig index")
      .def_readonly("index", &SimFrame::index, "frame number of this sensor")
      .def_readonly("stamp_ns", &SimFrame::stamp_ns)
      .def_readonly("t", &SimFrame::t, "s since the start")
      .def_readonly("map_T_base", &SimFrame::map_T_base)
      .def_readonly("map_T_sensor", &SimFrame::map_T_sensor)
      .def_property_readonly("exact", [](pb::object self) { return frameView(self, &SimFrame::exact); })
      .def_property_readonly("measured", [](pb::object self) { return frameView(self, &SimFrame::measured); })
      .def_property_readonly("artefacts", [](pb::object self) { return frameView(self, &SimFrame::artefacts); })
      .def_property_readonly("label", [](pb::object self) { return frameView(self, &SimFrame::label); })
      .def("__repr__", [](const SimFrame& f) {
  using namespace simulator_impl;
        return fmt::format("<polyloc.SimFrame sensor {} #{} t={:.3f} s, {} beams>", f.sensor, f.index, f.t, f.measured.size());
      });

  pb::dict bits;
  bits["miss"] = int(kArtefactMiss), bits["dropout"] = int(kArtefactDropout), bits["max_range"] = int(kArtefactMaxRange);
  bits["glass_passed"] = int(kArtefactGlassPassed), bits["glass_mirrored"] = int(kArtefactGlassMirrored);
  bits["flying_pixel"] = int(kArtefactFlyingPixel), bits["reflection"] = int(kArtefactReflection);
  bits["dark"] = int(kArtefactDark);
  m.attr("ARTEFACT_BITS") = bits;

  pb::class_<PySimulator>(m, "Simulator", R"(Drives the robot along a scenario's route and simulates every sensor, odometry and ground truth.

    sim = Simulator(load_scenario("maps/scenarios/lab_tour.yaml", duration=5))
    sim.run("run.mcap")                                  # ROS 2 messages as MCAP (else a bag directory)
    sim.run(on_frame=frames.append, on_tick=lambda t, truth, odom: ...)   # or through callbacks

Callbacks run on the calling thread, in time order within each simulated second (ticks of the
second first, then its frames); `polyloc.simulate` collects both into one time-ordered run.)")
      .def(pb::init([](const Scenario& s) {
  using namespace simulator_impl;
             auto p = std::make_unique<PySimulator>();
             pb::gil_scoped_release nogil;
             p->sim = std::make_unique<Simulator>(s, loadScenarioMap(s));
             return p;
           }),
           pb::arg("scenario"), "Loads the scenario's map and builds its world (chairs moved, world changes).")
      .def_property_readonly("duration", [](const PySimulator& s) { return s.sim->duration(); }, "s")
      .def_property_readonly("scenario", [](const PySimulator& s) { return s.sim->scenario(); })
      .def_property_readonly("rig", [](const PySimulator& s) { return s.sim->scenario().config.rig; })
      .def_property_readonly("world", [](const PySimulator& s) { return std::make_shared<Mesh>(s.sim->world()); },
                             "what the sensors see: the map with chairs moved and the scenario's world changes, label 'person'; a copy")
      .def("ground_truth", [](const PySimulator& s, double t) { return s.sim->groundTruth(t); }, pb::arg("t"),
           "map_T_base at t seconds")
      .def("run", &runSimulation, pb::arg("out") = "", pb::arg("on_frame") = pb::none(), pb::arg("on_tick") = pb::none(),
           pb::arg("on_progress") = pb::none(),
           R"(Simulate the whole scenario. out: '*.mcap', a ROS 2 bag directory, or '' for none.

on_frame(SimFrame), on_tick(stamp_ns, map_T_base, odom_T_base) at the odometry rate,
on_progress(fraction). Returns a summary dict (sim_duration_s, messages, topics, ...).)");
}

}  // namespace polyloc::py
