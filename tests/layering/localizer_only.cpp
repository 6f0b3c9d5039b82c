// A controller's view of the libraries: this program links polyloc::mcl alone (the localiser,
// the map, the ray casters) and tracks a robot in a room. It fails to link when the localiser
// reaches into a layer it must not need (recordings, simulator), and ctest's
// layering.localizer_needs check reads its dynamic section for the recording readers' libraries.
#include <polyloc/map/mesh.hpp>
#include <polyloc/mcl/localizer.hpp>
#include <polyloc/raycast/factory.hpp>

#include <cmath>
#include <cstdio>

using namespace polyloc;

int main() {
  // A 6 x 4 m room with a cabinet that breaks its symmetry.
  Mesh room;
  room.addBox({-3.2, -2.2, 0}, {3.2, -2.0, 2.5}, 1);
  room.addBox({-3.2, 2.0, 0}, {3.2, 2.2, 2.5}, 1);
  room.addBox({-3.2, -2.0, 0}, {-3.0, 2.0, 2.5}, 1);
  room.addBox({3.0, -2.0, 0}, {3.2, 2.0, 2.5}, 1);
  room.addBox({1.5, 0.8, 0}, {2.8, 1.9, 1.0}, 2);
  room.addBox({-3.2, -2.2, -0.1}, {3.2, 2.2, 0}, 3);  // floor
  const auto caster = makeCaster("embree", room);

  PlanarScannerSpec spec;
  spec.fov_rad = 270.0 * M_PI / 180.0;
  spec.resolution_rad = M_PI / 180.0;
  spec.range_max = 10.0;
  Rig rig;
  rig.name = "one scanner";
  rig.add(Sensor{"front", spec, Pose::fromXYZRPY(0.1, 0, 0.2, 0, 0, 0)}, "");

  MclConfig config;
  config.particles = 500;
  Localizer loc(*caster, room, rig, config);
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  cov(0, 0) = cov(1, 1) = 0.2 * 0.2, cov(5, 5) = 0.2 * 0.2;
  Pose truth = Pose::planar(-1.5, -0.5, 0.3);
  if (!loc.initPose(Pose::planar(-1.3, -0.6, 0.4), cov, 0)) return std::puts("initPose refused"), 1;
  const BeamSet beams = rig.sensors[0].beams();
  std::vector<float> ranges(beams.size());
  std::vector<Pose> path;  // the true pose at step i (t = i * 0.1 s)
  for (int i = 0; i < 40; ++i) {  // straight on at 0.05 m per step, exact odometry
    const int64_t t = int64_t(i) * 100'000'000;
    truth = truth * Pose::planar(0.05, 0, 0.01);
    path.push_back(truth);
    loc.addOdometry(t, truth);
    const Pose sensor = rig.sensors[0].worldPose(truth);
    HitBuffers out;
    out.range = ranges.data();
    caster->castScans(std::span<const Pose>(&sensor, 1), beams, out);
    loc.addScan(0, t, ranges);
  }
  const MclEstimate e = loc.estimate();
  // The estimate holds at the stamp of its round's last frame.
  const Pose& at = path[size_t(e.stamp_ns / 100'000'000)];
  const double err = (e.pose.translation() - at.translation()).head<2>().norm();
  std::printf("localizer_only: %s, error %.4f m after %llu updates\n", toString(e.status), err,
              static_cast<unsigned long long>(e.updates));
  return e.status == MclStatus::Tracking && err < 0.02 ? 0 : 1;
}
