// Simulated sensor data against exact ray casts: Gaussian noise statistics, artefact rates,
// glass (transparent / mirror / opaque), people in the scans, ToF depth, amplitude and flying
// pixels. All in the closed box room of fixtures.hpp with a robot standing still.
#include "sim_fixtures.hpp"

#include <polyloc/mapgen/builder.hpp>
#include <polyloc/raycast/embree.hpp>

#include <gtest/gtest.h>

#include <cmath>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_sim_sensors {

using namespace polyloc;


struct Stats {
  double n = 0, sum = 0, sum2 = 0;
  void add(double x) { ++n, sum += x, sum2 += x * x; }
  double mean() const { return sum / n; }
  double std() const { return std::sqrt(sum2 / n - mean() * mean()); }
};

// Runs a scenario and returns its frames.
std::vector<SimFrame> frames(Scenario s, const Mesh& map, test::CaptureWriter* out = nullptr) {
  Simulator sim(std::move(s), map);
  std::vector<SimFrame> fs;
  test::CaptureWriter local;
  SimHooks hooks;
  hooks.on_frame = [&](const SimFrame& f) { fs.push_back(f); };
  sim.run(out ? *out : local, hooks);
  return fs;
}

// Exact ranges of a frame by an independent cast (default caster options).
std::vector<float> castExact(const EmbreeCaster& caster, const Sensor& sensor, const SimFrame& f) {
  const BeamSet b = sensor.beams();
  std::vector<float> r(b.size());
  caster.castScans(std::vector<Pose>{f.map_T_sensor}, b, {r.data()});
  return r;
}

Mesh room() { return test::boxRoom(4.f, 3.f, 2.5f, 0.2f); }

// Room with a pillar labelled "cabinet" in front of the origin (depth discontinuities, specular).
Mesh roomWithPillar() {
  Mesh m = room();
  mapgen::MeshBuilder b(m);
  b.box({1.5f, -0.3f, 0.f}, {1.9f, 0.3f, 2.5f}, "cabinet");
  return m;
}


TEST(SimSensors, RangeNoiseMatchesSettingsPerModel) {
  const Mesh map = room();
  const EmbreeCaster caster(map);
  struct Case {
    std::string preset;
    Sensor sensor;
  };
  const std::vector<Case> cases = {
      {"sick_s300", {"s300", sickS300(), Pose::fromXYZRPY(0, 0, 0.1, 0, 0, 0.3)}},
      {"sick_lms200", {"lms", sickLMS200(), Pose::fromXYZRPY(0.2, 0, 0.2, 0, 0, 0)}},
      {"hokuyo_urg04lx", {"urg", hokuyoURG04LX(), Pose::fromXYZRPY(0, 0, 1.0, 0, deg2rad(40), 0)}},
      {"pmd_o3d100", {"tof", pmdO3D100(), Pose::fromXYZRPY(0, 0, 0.75, 0, deg2rad(10), 0)}},
  };
  for (const Case& c : cases) {
    Scenario s = test::roomScenario(c.sensor, c.preset, 4.0);
    const SensorNoise noise = s.noise.sensors[0];
    Stats raw, normalised;
    for (const SimFrame& f : frames(s, map)) {
      const std::vector<float> exact = castExact(caster, c.sensor, f);
      for (size_t b = 0; b < exact.size(); ++b) {
        if (f.artefacts[b] != kArtefactNone || !std::isfinite(exact[b])) continue;
        ASSERT_NEAR(f.exact[b], exact[b], 1e-4) << c.preset;  // the simulator's own exact range
        const double e = f.measured[b] - exact[b];
        raw.add(e);
        normalised.add(e / noise.sigmaAt(exact[b]));
      }
    }
    ASSERT_GT(raw.n, 5000) << c.preset;
    EXPECT_NEAR(raw.mean(), 0.0, 0.002) << c.preset;        // unbiased within 2 mm
    EXPECT_NEAR(normalised.std(), 1.0, 0.1) << c.preset;    // std within 10 % of the setting
    if (noise.sigma_rel == 0 && noise.sigma_slope == 0) {
      EXPECT_NEAR(raw.std(), noise.sigma, 0.1 * noise.sigma) << c.preset;
    }
  }
}

TEST(SimSensors, NoiseOffGivesExactRanges) {
  Scenario s = test::roomScenario({"s", sickS300(), Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)}, "sick_s300", 0.5);
  s.noise.enabled = false;
  for (const SimFrame& f : frames(s, room()))
    for (size_t b = 0; b < f.measured.size(); ++b) ASSERT_EQ(f.measured[b], f.exact[b]);
}

TEST(SimSensors, DropoutAndMaxRangeRates) {
  Scenario s = test::roomScenario({"s", sickLMS200(), Pose::fromXYZRPY(0, 0, 0.3, 0, 0, 0)}, "sick_lms200", 6.0);
  s.noise.sensors[0].dropout = 0.05;
  s.noise.sensors[0].max_range = 0.02;
  double returns = 0, dropped = 0, maxed = 0;
  test::CaptureWriter w;
  for (const SimFrame& f : frames(s, room(), &w)) {
    for (size_t b = 0; b < f.exact.size(); ++b) {
      if (f.artefacts[b] & kArtefactMiss) continue;
      ++returns;
      if (f.artefacts[b] & kArtefactDropout) {
        ++dropped;
        EXPECT_TRUE(std::isnan(f.measured[b]));
      } else if (f.artefacts[b] & kArtefactMaxRange) {
        ++maxed;
        EXPECT_EQ(f.measured[b], 8.0f);
      }
    }
  }
  ASSERT_GT(returns, 100000);
  // Binomial: 4 standard deviations.
  EXPECT_NEAR(dropped / returns, 0.05, 4 * std::sqrt(0.05 * 0.95 / returns));
  const double kept = returns - dropped;
  EXPECT_NEAR(maxed / kept, 0.02, 4 * std::sqrt(0.02 * 0.98 / kept));
  // The published scans carry the same values (NaN for dropouts).
  const auto scans = w.on("/scan/s");
  ASSERT_FALSE(scans.empty());
  const auto& scan = std::get<msg::LaserScan>(scans.front()->message);
  EXPECT_EQ(scan.ranges.size(), 361u);
  EXPECT_EQ(scan.header.frame_id, "s");
  EXPECT_FLOAT_EQ(scan.angle_min, static_cast<float>(-M_PI / 2));
  EXPECT_FLOAT_EQ(scan.range_max, 8.f);
}

TEST(SimSensors, GlassTransparentMirrorOpaque) {
  // A glass pane across the room at x = 2 (2 cm thick); the scanner at the origin looks at it.
  Mesh map = room();
  mapgen::MeshBuilder b(map);
  b.box({1.99f, -3.f, 0.f}, {2.01f, 3.f, 2.5f}, "glass");
  PlanarScannerSpec narrow = sickLMS200();
  narrow.fov_rad = deg2rad(10), narrow.range_max = 30;
  const Sensor sensor{"s", narrow, Pose::fromXYZRPY(0, 0, 1.0, 0, 0, 0)};
  auto centreBeam = [&](GlassMode mode, uint8_t* tag) {
    Scenario s = test::roomScenario(sensor, "sick_lms200", 0.05);
    s.noise.enabled = false;
    s.noise.glass = mode;
    const auto fs = frames(s, map);
    const SimFrame& f = fs.front();
    const size_t mid = f.exact.size() / 2;
    *tag = f.artefacts[mid];
    return f.exact[mid];
  };
  uint8_t tag;
  EXPECT_NEAR(centreBeam(GlassMode::Opaque, &tag), 1.99, 1e-4);
  EXPECT_EQ(tag, kArtefactNone);
  EXPECT_NEAR(centreBeam(GlassMode::Transparent, &tag), 4.0, 1e-3);  // the wall behind the pane
  EXPECT_EQ(tag, kArtefactGlassPassed);
  EXPECT_NEAR(centreBeam(GlassMode::Mirror, &tag), 1.99 + 1.99 + 4.0, 1e-3);  // back to the wall behind
  EXPECT_EQ(tag, kArtefactGlassMirrored);
  // The per-sensor setting overrides the scenario's.
  Scenario s = test::roomScenario(sensor, "sick_lms200", 0.05);
  s.noise.enabled = false;
  s.noise.glass = GlassMode::Transparent;
  s.noise.sensors[0].glass = GlassMode::Opaque;
  EXPECT_NEAR(frames(s, map).front().exact[frames(s, map).front().exact.size() / 2], 1.99, 1e-4);
}

TEST(SimSensors, PeopleAppearInScans) {
  const Mesh map = room();
  const Sensor sensor{"s", sickS300(), Pose::fromXYZRPY(0, 0, 1.0, 0, 0, 0)};  // torso height
  Scenario s = test::roomScenario(sensor, "sick_s300", 0.05);
  s.noise.enabled = false;
  PersonSpec p;
  p.waypoints = {{2.0, 0.0}};  // standing 2 m ahead, facing +x
  s.people = {p};
  Simulator sim(s, map);
  std::vector<SimFrame> fs;
  test::CaptureWriter w;
  SimHooks hooks;
  hooks.on_frame = [&](const SimFrame& f) { fs.push_back(f); };
  sim.run(w, hooks);
  const SimFrame& f = fs.front();
  const size_t mid = f.exact.size() / 2;
  EXPECT_NEAR(f.exact[mid], 2.0 - 0.12, 1e-4);  // the front of the torso
  EXPECT_EQ(f.label[mid], sim.personLabel());
  EXPECT_EQ(sim.world().label_names[sim.personLabel()], "person");
  // About 0.5 m wide (arms included) at 2 m: beams within +-7 deg hit the person, at 10 deg not.
  const double res = sickS300().resolution_rad;
  EXPECT_EQ(f.label[mid + static_cast<size_t>(deg2rad(6.5) / res)], sim.personLabel());
  EXPECT_NE(f.label[mid + static_cast<size_t>(deg2rad(10) / res)], sim.personLabel());
  EXPECT_NEAR(f.exact[mid + static_cast<size_t>(deg2rad(20) / res)], 4.0 / std::cos(deg2rad(20)), 1e-3);
  // A person walking across: the beam towards the crossing point is shorter only while they pass.
  PersonSpec walker;
  walker.waypoints = {{2.0, -2.5}, {2.0, 2.5}};
  walker.loop = false;
  walker.speed = 1.0;
  s.people = {walker};
  s.duration = 5.0;
  size_t shorter = 0, total = 0;
  for (const SimFrame& g : frames(s, map)) {
    ++total;
    shorter += g.exact[mid] < 3.0f;
  }
  EXPECT_GT(shorter, 0u);
  EXPECT_LT(shorter, total / 3);
}

TEST(SimSensors, TofDepthImageAmplitudeAndCameraInfo) {
  const Sensor cam{"tof", pmdO3D100(), Pose::fromXYZRPY(0, 0, 1.2, 0, 0, 0)};  // sees only the wall
  Scenario s = test::roomScenario(cam, "pmd_o3d100", 0.05);
  s.noise.enabled = false;
  test::CaptureWriter w;
  const auto fs = frames(s, room(), &w);
  const auto img = std::get<msg::Image>(w.on("/depth/tof/image").front()->message);
  EXPECT_EQ(img.encoding, "32FC1");
  EXPECT_EQ(img.header.frame_id, "tof_optical");
  ASSERT_EQ(img.width, 64u);
  ASSERT_EQ(img.height, 50u);
  ASSERT_EQ(img.data.size(), 64u * 50u * 4u);
  std::vector<float> depth(64 * 50);
  std::memcpy(depth.data(), img.data.data(), img.data.size());
  // Facing the wall at x = 4 head on: every pixel's depth is 4 m.
  for (float d : depth) ASSERT_NEAR(d, 4.0, 1e-4);
  const auto amp = std::get<msg::Image>(w.on("/depth/tof/amplitude").front()->message);
  std::vector<float> a(64 * 50);
  std::memcpy(a.data(), amp.data.data(), amp.data.size());
  // Brightest in the centre (head on, nearest), falling towards the corners.
  EXPECT_NEAR(a[25 * 64 + 32], 1000 * 0.8 / 16.0, 2.0);
  EXPECT_LT(a[0], a[25 * 64 + 32]);
  const auto info = std::get<msg::CameraInfo>(w.on("/depth/tof/camera_info").front()->message);
  EXPECT_NEAR(info.k[0], pmdO3D100().fx(), 1e-9);
  EXPECT_NEAR(info.k[2], 31.5, 1e-12);
  EXPECT_NEAR(info.k[5], 24.5, 1e-12);
  // Projecting a depth pixel with K gives back its ray: pixel (0, 0) in the optical frame.
  const BeamSet beams = cam.beams();
  const double x = (0 - info.k[2]) / info.k[0], y = (0 - info.k[5]) / info.k[4];
  EXPECT_NEAR(-x / std::sqrt(x * x + y * y + 1), beams.dy[0], 1e-6);  // optical x = -body y
  EXPECT_NEAR(-y / std::sqrt(x * x + y * y + 1), beams.dz[0], 1e-6);  // optical y = -body z
  // tf_static: base -> tof and tof -> tof_optical (z forward, x right, y down).
  const auto tf = std::get<msg::TFMessage>(w.on("/tf_static").front()->message);
  ASSERT_EQ(tf.transforms.size(), 2u);
  EXPECT_EQ(tf.transforms[1].header.frame_id, "tof");
  EXPECT_EQ(tf.transforms[1].child_frame_id, "tof_optical");
  const auto& q = tf.transforms[1].transform.rotation;
  const Eigen::Matrix3d R = Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix();
  EXPECT_TRUE(R.col(2).isApprox(Eigen::Vector3d(1, 0, 0), 1e-12));   // optical z = body x
  EXPECT_TRUE(R.col(0).isApprox(Eigen::Vector3d(0, -1, 0), 1e-12));  // optical x = -body y
}

TEST(SimSensors, FlyingPixelAndReflectionOutlierRates) {
  const Mesh map = roomWithPillar();
  const Sensor cam{"tof", pmdO3D100(), Pose::fromXYZRPY(0, 0, 1.0, 0, 0, 0)};
  Scenario s = test::roomScenario(cam, "pmd_o3d100", 8.0);
  SensorNoise& n = s.noise.sensors[0];
  n.dropout = 0, n.max_range = 0;
  n.flying_pixel = 0.4, n.flying_threshold = 0.3;
  n.reflection_outlier = 0.1, n.specular_labels = {"cabinet"};
  const std::vector<float> factor = pmdO3D100().depthFactors();
  const int64_t cabinet = map.findLabel("cabinet");
  double edge = 0, flying = 0, specular = 0, reflected = 0;
  for (const SimFrame& f : frames(s, map)) {
    auto depth = [&](int u, int v) { return f.exact[v * 64 + u] * factor[v * 64 + u]; };
    for (int v = 0; v < 50; ++v)
      for (int u = 0; u < 64; ++u) {
        const size_t b = v * 64 + u;
        if (f.label[b] == static_cast<uint32_t>(cabinet)) {
          ++specular;
          if (f.artefacts[b] & kArtefactReflection) {
            ++reflected;
            EXPECT_LT(f.measured[b], 0.85 * f.exact[b]);  // implausibly short
            EXPECT_GT(f.measured[b], 0.15 * f.exact[b]);
          }
          continue;  // reflection is tried first on specular pixels
        }
        float step = 0, other = depth(u, v);
        for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          if (u + du < 0 || u + du >= 64 || v + dv < 0 || v + dv >= 50) continue;
          const float d = depth(u + du, v + dv);
          if (std::abs(d - depth(u, v)) > step) step = std::abs(d - depth(u, v)), other = d;
        }
        const bool at_edge = step > 0.3f;
        if (!at_edge) {
          ASSERT_FALSE(f.artefacts[b] & kArtefactFlyingPixel);
          continue;
        }
        ++edge;
        if (f.artefacts[b] & kArtefactFlyingPixel) {
          ++flying;
          const float dm = f.measured[b] * factor[b];  // between fore- and background (+ noise)
          EXPECT_GT(dm, std::min(depth(u, v), other) - 0.05f);
          EXPECT_LT(dm, std::max(depth(u, v), other) + 0.05f);
        }
      }
  }
  ASSERT_GT(edge, 2000);
  ASSERT_GT(specular, 20000);
  EXPECT_NEAR(flying / edge, 0.4, 4 * std::sqrt(0.4 * 0.6 / edge));
  EXPECT_NEAR(reflected / specular, 0.1, 4 * std::sqrt(0.1 * 0.9 / specular));
}

TEST(SimSensors, LidarPointCloud) {
  const Sensor lidar{"vlp", velodyneVLP16(), Pose::fromXYZRPY(0, 0, 1.0, 0, 0, 0)};
  Scenario s = test::roomScenario(lidar, "vlp16", 0.05);
  test::CaptureWriter w;
  const auto fs = frames(s, room(), &w);
  const auto pc = std::get<msg::PointCloud2>(w.on("/points/vlp").front()->message);
  EXPECT_EQ(pc.header.frame_id, "vlp");
  ASSERT_EQ(pc.fields.size(), 5u);
  EXPECT_EQ(pc.fields[4].name, "ring");
  EXPECT_EQ(pc.point_step, 20u);
  size_t valid = 0;
  for (float r : fs.front().measured) valid += std::isfinite(r);
  ASSERT_EQ(pc.width, valid);  // dropouts (NaN) are left out; the closed room has no misses
  EXPECT_GT(valid, 16u * 1800u * 9 / 10);
  EXPECT_EQ(pc.data.size(), valid * 20u);
  // The first point: beam 0 (layer 0 at -15 deg, azimuth 0) unless it dropped out.
  float p[3];
  std::memcpy(p, pc.data.data(), sizeof(p));
  const float r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  EXPECT_NEAR(std::asin(p[2] / r), deg2rad(-15), 1e-4);
  EXPECT_NEAR(r, 1.0 / std::sin(deg2rad(15)), 0.15);  // the floor, 1 m below
}

}  // namespace polyloc::t_sim_sensors
