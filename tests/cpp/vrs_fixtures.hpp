// Helpers of the VRS scenario tests: a simulated drive with the lisa rig fed frame by frame into
// a VirtualRangeScanner at the ground-truth pose (what localisation gives), with a callback
// after every update; small worlds built in code.
#pragma once

#include "sim_fixtures.hpp"

#include <polyloc/mapgen/builder.hpp>
#include <polyloc/sensors/rig.hpp>
#include <polyloc/tracking/people_tracker.hpp>
#include <polyloc/vrs/moving_objects.hpp>
#include <polyloc/vrs/virtual_scan.hpp>

#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>

namespace polyloc::test {

struct VrsStep {
  double t = 0;            // s since the start
  const VirtualScan& scan;                // of the first scanner
  const std::vector<VirtualScan>& scans;  // of each scanner run
  const Pose& truth;       // map_T_base
  const Simulator& sim;
};

// Lisa on a straight route from `from` to `to` (then standing `wait` s), in `map`; the VRS is
// updated after every frame of the first S300. `people`: walking in the scene; moving(t) gives
// the tracked objects for the memory filter (empty function: none).
struct VrsDrive {
  Mesh map;
  Eigen::Vector2d from{0, 0}, to{1, 0};
  double speed = 0.3, wait = 5.0;
  std::vector<PersonSpec> people;
  VrsConfig config;
  std::function<std::vector<MovingObject>(double t, const Simulator&)> moving;
  bool noise = true;
  bool clean_tof = true;  // lisa's ToF (rig sensor 6) without its outliers
  bool track_people = false;  // the moving objects from tracking/ (PeopleTracker on the S300s)
  TrackingConfig tracking;
};

inline Scenario vrsScenario(const VrsDrive& d) {
  Scenario s;
  s.config.robot.footprint = {{0.3, 0.25}, {-0.3, 0.25}, {-0.3, -0.25}, {0.3, -0.25}};
  s.config.robot.height = 1.2;
  s.config.rig = rigPreset("lisa");
  s.noise.enabled = d.noise;
  s.noise.sensors = defaultSensorNoise(s.config.rig);
  s.route.waypoints = {Waypoint{d.from, std::nullopt, 0.0, true}, Waypoint{d.to, std::nullopt, d.wait, true}};
  s.route.max_speed = d.speed;
  s.route.start_pause = 0.5;
  s.people = d.people;
  return s;
}

// Every scanner in `vrs` gets the same frames and updates; the step carries the first one's scan
// and all of them (in the order given).
inline void runVrs(const VrsDrive& d, std::initializer_list<VirtualRangeScanner*> vrs,
                   const std::function<void(const VrsStep&)>& on_update) {
  Simulator sim(vrsScenario(d), d.map);
  NullRecordingWriter sink;  // the recording itself is not needed; frames come through the hook
  SimHooks hooks;
  std::optional<PeopleTracker> people;
  if (d.track_people) people.emplace(sim.scenario().config.rig, d.tracking);
  std::vector<VirtualScan> scans(vrs.size());
  hooks.on_frame = [&](const SimFrame& f) {
    if (people) {
      people->addScan(f.sensor, f.stamp_ns, f.map_T_sensor, f.measured);
      if (f.sensor == 0) {
        people->flush();
        for (VirtualRangeScanner* v : vrs) v->setMovingObjects(movingObjects(people->tracks()));
      }
    }
    std::vector<float> r = f.measured;
    if (d.clean_tof && f.sensor == 6) {
      // ToF outliers (flying pixels, reflections) removed, as the depth filters do before the
      // VRS: here by the simulator's own tags.
      for (size_t i = 0; i < r.size(); ++i)
        if (f.artefacts[i] & (kArtefactFlyingPixel | kArtefactReflection)) r[i] = std::numeric_limits<float>::quiet_NaN();
    }
    for (VirtualRangeScanner* v : vrs) v->addFrame(f.sensor, f.stamp_ns, f.map_T_base, r);
    if (f.sensor != 0) return;
    const std::vector<MovingObject> m = d.moving ? d.moving(f.t, sim) : std::vector<MovingObject>{};
    size_t k = 0;
    for (VirtualRangeScanner* v : vrs) {
      if (d.moving) v->setMovingObjects(m);
      scans[k++] = v->update(f.stamp_ns, f.map_T_base);
    }
    on_update(VrsStep{f.t, scans.front(), scans, f.map_T_base, sim});
  };
  sim.run(sink, hooks);
}

inline void runVrs(const VrsDrive& d, VirtualRangeScanner& vrs, const std::function<void(const VrsStep&)>& on_update) {
  runVrs(d, {&vrs}, on_update);
}

// The ground-truth people as tracked objects (position, 10 cm std).
inline std::vector<MovingObject> truePeople(double t, const Simulator& sim) {
  std::vector<MovingObject> out;
  const Pose robot = sim.groundTruth(t);
  for (size_t i = 0; i < sim.people().size(); ++i) {
    const PersonState p = sim.people().state(i, t, robot.translation().head<2>());
    if (p.present) out.push_back({{p.x, p.y}, {p.vx, p.vy}, Eigen::Matrix2d::Identity() * 0.01, sim.scenario().start_time_ns + int64_t(t * 1e9)});
  }
  return out;
}

// Range of the segment containing direction `deg` (base frame).
inline float vrsAt(const VirtualScan& v, double deg) {
  double a = std::remainder(deg2rad(deg) - v.angle_min, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return v.ranges[std::min(v.size() - 1, size_t(a / v.angle_increment))];
}

// A closed room [x0, x1] x [y0, y1], walls 2.5 m high.
inline Mesh roomMesh(float x0, float y0, float x1, float y1) {
  Mesh m;
  mapgen::MeshBuilder b(m);
  const float t = 0.2f, h = 2.5f;
  b.box({x0 - t, y0 - t, -t}, {x1 + t, y1 + t, 0}, "floor");
  b.box({x0 - t, y0 - t, 0}, {x0, y1 + t, h}, "wall");
  b.box({x1, y0 - t, 0}, {x1 + t, y1 + t, h}, "wall");
  b.box({x0, y0 - t, 0}, {x1, y0, h}, "wall");
  b.box({x0, y1, 0}, {x1, y1 + t, h}, "wall");
  return m;
}

// A four-legged chair: seat [cx - 0.23, cx + 0.23] square at 0.42-0.47 m, 3 cm legs at the corners,
// a backrest on the +x side up to 0.9 m.
inline void addStool(Mesh& m, float cx, float cy, bool backrest = true) {
  mapgen::MeshBuilder b(m);
  const float s = 0.23f, l = 0.03f;
  b.box({cx - s, cy - s, 0.42f}, {cx + s, cy + s, 0.47f}, "chair");
  for (float sx : {-1.f, 1.f})
    for (float sy : {-1.f, 1.f}) {
      const float x = cx + sx * (s - l), y = cy + sy * (s - l);
      b.box({x - l / 2, y - l / 2, 0.f}, {x + l / 2, y + l / 2, 0.42f}, "chair");
    }
  if (backrest) b.box({cx + s - 0.03f, cy - s, 0.47f}, {cx + s, cy + s, 0.9f}, "chair");
}

}  // namespace polyloc::test
