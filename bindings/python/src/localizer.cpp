// The Monte-Carlo localiser. The Python object owns (or shares) what the C++ Localizer only
// references: the mesh, the caster, the rig and the settings.
#include "common.hpp"

#include <polyloc/configfile/polyloc_config.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/embree.hpp>

#include <pybind11/stl.h>

#include <fmt/format.h>

#include <memory>
#include <mutex>

namespace polyloc::py {

namespace localizer_impl {  // named, not anonymous: the module is compiled in batches (unity build)

struct PyLocalizer {
  std::shared_ptr<const Mesh> mesh;
  std::shared_ptr<const EmbreeCaster> caster;
  Rig rig;
  MclConfig config;
  std::unique_ptr<RayCaster> weigh;  // mcl.caster other than embree
  std::unique_ptr<Localizer> loc;
  std::mutex mutex;

  PyLocalizer(std::shared_ptr<const EmbreeCaster> c, std::shared_ptr<const Mesh> m, Rig r, MclConfig cfg)
      : mesh(std::move(m)), caster(std::move(c)), rig(std::move(r)), config(std::move(cfg)) {
    pb::gil_scoped_release nogil;
    weigh = makeWeighingCaster(*mesh, rig, config, config.threads);
    loc = std::make_unique<Localizer>(*caster, *mesh, rig, config, weigh.get());
  }

  size_t sensorIndex(const pb::handle& sensor) const {
    if (pb::isinstance<pb::str>(sensor)) {
      const int i = rig.find(sensor.cast<std::string>());
      if (i < 0) raise(PyExc_ValueError, fmt::format("sensor '{}' is not in rig '{}' (sensors: {})", sensor.cast<std::string>(),
                                                     rig.name, fmt::join(names(), ", ")));
      return static_cast<size_t>(i);
    }
    const int64_t i = sensor.cast<int64_t>();
    if (i < 0 || static_cast<size_t>(i) >= rig.size())
      raise(PyExc_ValueError, fmt::format("sensor index {} out of range: rig '{}' has {} sensors", i, rig.name, rig.size()));
    return static_cast<size_t>(i);
  }
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& s : rig.sensors) n.push_back(s.name);
    return n;
  }
};

std::unique_ptr<PyLocalizer> fromConfig(const PolylocConfig& cfg, std::shared_ptr<const Mesh> mesh,
                                        std::shared_ptr<const EmbreeCaster> caster) {
  if (!mesh) {
    pb::gil_scoped_release nogil;
    mesh = std::make_shared<Mesh>(loadMesh(cfg.map.file, cfg.map.load));
  }
  if (!caster) {
    EmbreeOptions o;
    o.threads = cfg.mcl.threads;
    pb::gil_scoped_release nogil;
    caster = std::make_shared<EmbreeCaster>(*mesh, o);
  }
  return std::make_unique<PyLocalizer>(caster, mesh, cfg.rig, cfg.mcl);
}

// The CLI's default start spread (polyloc localize --init-sigma 0.1,5).
Eigen::Matrix<double, 6, 6> defaultCovariance() {
  Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
  c.diagonal() << 0.01, 0.01, 0.02 * 0.02, deg2rad(1) * deg2rad(1), deg2rad(1) * deg2rad(1), deg2rad(5) * deg2rad(5);
  return c;
}

pb::dict counters(const MclCounters& c) {
  pb::dict d;
#define POLYLOC_COUNTER(f) d[#f] = c.f;
  POLYLOC_COUNTER(odometry) POLYLOC_COUNTER(odometry_out_of_order) POLYLOC_COUNTER(odometry_gaps)
  POLYLOC_COUNTER(odometry_invalid) POLYLOC_COUNTER(particles_blocked) POLYLOC_COUNTER(blocked_ignored)
  POLYLOC_COUNTER(weights_collapsed) POLYLOC_COUNTER(scans) POLYLOC_COUNTER(scans_rejected) POLYLOC_COUNTER(updates)
  POLYLOC_COUNTER(resamples) POLYLOC_COUNTER(injected) POLYLOC_COUNTER(relocalizations) POLYLOC_COUNTER(refinements)
  POLYLOC_COUNTER(refinements_refused) POLYLOC_COUNTER(hypotheses)
  POLYLOC_COUNTER(recoveries) POLYLOC_COUNTER(jumps) POLYLOC_COUNTER(inconsistent)
#undef POLYLOC_COUNTER
  return d;
}

pb::dict particles(const ParticleSet& p) {
  pb::dict d;
  d["x"] = toArray(p.x), d["y"] = toArray(p.y), d["z"] = toArray(p.z);
  d["qw"] = toArray(p.qw), d["qx"] = toArray(p.qx), d["qy"] = toArray(p.qy), d["qz"] = toArray(p.qz);
  d["logw"] = toArray(p.logw);
  return d;
}

}  // namespace localizer_impl

void bindLocalizer(pb::module_& m) {
  using namespace localizer_impl;
  pb::class_<MclEstimate>(m, "Estimate", "A pose estimate of the localiser.")
      .def_readonly("stamp_ns", &MclEstimate::stamp_ns)
      .def_readonly("pose", &MclEstimate::pose, "map_T_base")
      .def_property_readonly("covariance", [](const MclEstimate& e) { return matrixArray(e.covariance); },
                             "(6, 6) float64 over x, y, z, roll, pitch, yaw")
      .def_property_readonly("status", [](const MclEstimate& e) { return std::string(toString(e.status)); },
                             "'initialising', 'tracking', 'uncertain' or 'lost'")
      .def_readonly("ess", &MclEstimate::ess, "effective sample size of the last weighting")
      .def_readonly("particles", &MclEstimate::particles)
      .def_readonly("updates", &MclEstimate::updates)
      .def_readonly("refined", &MclEstimate::refined)
      .def("to_dict", [](const MclEstimate& e) {
        pb::dict d;
        d["stamp_ns"] = e.stamp_ns, d["pose"] = e.pose, d["covariance"] = matrixArray(e.covariance);
        d["status"] = toString(e.status), d["ess"] = e.ess, d["particles"] = e.particles, d["updates"] = e.updates;
        d["refined"] = e.refined;
        return d;
      })
      .def("__repr__", [](const MclEstimate& e) {
        return fmt::format("<polyloc.Estimate {} x={:.3f} y={:.3f} yaw={:.3f} ({} particles, {} updates)>", toString(e.status),
                           e.pose.x(), e.pose.y(), e.pose.yaw(), e.particles, e.updates);
      });

  pb::class_<PyLocalizer>(m, "Localizer", R"(Monte-Carlo localisation over a polygon map (6-DoF particles weighed with Embree).

    loc = Localizer(load_config("maps/config/lab.yaml"))   # loads the map, builds the caster
    loc.init_pose(Pose.planar(1.3, 1.75, 0.0), stamp_ns=t0)  # or loc.init_global(t0)
    loc.add_odometry(t, odom_T_base); loc.add_scan("s300_front_left", t, ranges)
    e = loc.estimate()                                      # pose, covariance, status, ...

add_scan returns True when the call ended a round of measurement updates (the estimate is new).
Scans with NaN/inf beams are fine (invalid beams); a wrong number of ranges is a ValueError.
Calls release the GIL; one Localizer serves one thread at a time.)")
      .def(pb::init(&fromConfig), pb::arg("config"), pb::arg("mesh") = nullptr, pb::arg("caster") = nullptr,
           "From a Config: its rig and mcl settings; the map is loaded (and the caster built) unless given.")
      .def(pb::init([](std::shared_ptr<const EmbreeCaster> caster, std::shared_ptr<const Mesh> mesh, Rig rig, MclConfig mcl) {
  using namespace localizer_impl;
             return std::make_unique<PyLocalizer>(std::move(caster), std::move(mesh), std::move(rig), std::move(mcl));
           }),
           pb::arg("caster"), pb::arg("mesh"), pb::arg("rig"), pb::arg("mcl") = MclConfig{})
      .def("init_pose", [](PyLocalizer& l, const pb::handle& pose, const pb::handle& cov, int64_t stamp) {
        const Pose p = toPose(pose, "pose");
        const Eigen::Matrix<double, 6, 6> c = cov.is_none() ? defaultCovariance() : toCovariance(cov, "covariance");
        pb::gil_scoped_release nogil;
        Guard g(l.mutex);
        l.loc->initPose(p, c, stamp);
      }, pb::arg("pose"), pb::arg("covariance") = pb::none(), pb::arg("stamp_ns") = 0,
           "Start around map_T_base with a (6, 6) covariance (default: 0.1 m, 5 deg in yaw).")
      .def("init_global", [](PyLocalizer& l, int64_t stamp) {
        pb::gil_scoped_release nogil;
        Guard g(l.mutex);
        l.loc->initGlobal(stamp);
      }, pb::arg("stamp_ns") = 0, "Uniform over the free floor space where the robot can stand.")
      .def("add_odometry", [](PyLocalizer& l, int64_t stamp, const pb::handle& pose) {
        const Pose p = toPose(pose, "odom_T_base");
        pb::gil_scoped_release nogil;
        Guard g(l.mutex);
        l.loc->addOdometry(stamp, p);
      }, pb::arg("stamp_ns"), pb::arg("odom_T_base"), "Cumulative odometry pose; older than the last one: ignored and counted.")
      .def("add_scan", [](PyLocalizer& l, const pb::handle& sensor, int64_t stamp, const pb::handle& ranges) {
        const size_t s = l.sensorIndex(sensor);
        const F32Array r = rangesArray(ranges, "ranges", l.rig.sensors[s].beams().size());
        pb::gil_scoped_release nogil;
        Guard g(l.mutex);
        return l.loc->addScan(s, stamp, std::span<const float>(r.data(), static_cast<size_t>(r.size())));
      }, pb::arg("sensor"), pb::arg("stamp_ns"), pb::arg("ranges"),
           "One frame of a rig sensor (index or name): ranges (B,) in beam order (ToF: range along the ray).\n"
           "Returns True when this call ended a round (estimate() is new).")
      .def("estimate", [](PyLocalizer& l) {
        Guard g(l.mutex);
        return l.loc->estimate();
      })
      .def("particles", [](PyLocalizer& l) {
        Guard g(l.mutex);
        return particles(l.loc->particles());
      }, "Copies of the particle set: dict of x, y, z, qw, qx, qy, qz, logw (N,) float64 (log weights, normalised).")
      .def_property_readonly("counters", [](PyLocalizer& l) {
        Guard g(l.mutex);
        return counters(l.loc->counters());
      }, "Counted events and rejections (odometry, scans, scans_rejected, updates, resamples, ...)")
      .def_property_readonly("config", [](const PyLocalizer& l) { return l.config; }, "the MclConfig (a copy)")
      .def_property_readonly("rig", [](const PyLocalizer& l) { return l.rig; }, "the Rig (a copy)")
      .def_property_readonly("mesh", [](const PyLocalizer& l) { return std::const_pointer_cast<Mesh>(l.mesh); })
      .def_property_readonly("caster", [](const PyLocalizer& l) { return std::const_pointer_cast<EmbreeCaster>(l.caster); });
}

}  // namespace polyloc::py
