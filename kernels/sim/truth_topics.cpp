#include "truth_topics.hpp"

#include <polyloc/sim/vrs_truth.hpp>

#include <algorithm>
#include <cmath>

namespace polyloc::detail {

OutMessage peopleTruth(const SimFrame& f, const BeamSet& beams, const People& people, const PeopleScene& scene,
                       uint32_t person_label, const std::string& map_frame, int order) {
  // The end of each beam that hit a person, given to the person whose bounding box holds it
  // (scene.bounds: one box per person present, in the order of their boxes' ranges).
  std::vector<uint32_t> hits(scene.bounds.size(), 0);
  for (size_t b = 0; b < f.label.size() && b < f.exact.size() && b < beams.size(); ++b) {
    if (f.label[b] != person_label || !std::isfinite(f.exact[b])) continue;
    const Eigen::Vector3d p = f.map_T_sensor * Eigen::Vector3d(beams.dx[b] * f.exact[b], beams.dy[b] * f.exact[b], beams.dz[b] * f.exact[b]);
    for (size_t k = 0; k < scene.bounds.size(); ++k) {
      Eigen::AlignedBox3f box = scene.bounds[k];
      box.extend(box.min() - Eigen::Vector3f::Constant(0.02f)).extend(box.max() + Eigen::Vector3f::Constant(0.02f));
      if (box.contains(p.cast<float>())) {
        ++hits[k];
        break;
      }
    }
  }
  msg::TrackArray out;
  out.header = {msg::fromNs(f.stamp_ns), map_frame};
  const Eigen::Vector2d robot = f.map_T_base.translation().head<2>();
  size_t present = 0;  // index into scene.bounds: people present, in person order
  for (size_t i = 0; i < people.size(); ++i) {
    const PersonState s = people.state(i, f.t, robot);
    if (!s.present) continue;
    const uint32_t h = present < hits.size() ? hits[present] : 0;
    ++present;
    out.tracks.push_back({uint32_t(i), uint8_t(std::min<uint32_t>(h, 255)), s.x, s.y, s.vx, s.vy, {0.0025, 0, 0, 0.0025}});
  }
  return {f.stamp_ns, order, "/ground_truth/people", std::move(out)};
}

OutMessage vrsTruth(const SimFrame& f, const RayCaster& map, const PeopleScene& scene, const VrsConfig& config,
                    const std::string& base_frame, int order) {
  msg::LaserScan scan;
  scan.header = {msg::fromNs(f.stamp_ns), base_frame};
  scan.angle_increment = float(config.resolution);
  scan.angle_min = float(config.angle_min + 0.5 * config.resolution);  // the rays are at segment centres
  scan.ranges = trueVirtualScan(map, scene, f.map_T_base, config);
  scan.angle_max = scan.angle_min + float(scan.ranges.size() - 1) * scan.angle_increment;
  scan.range_min = 0.f;
  scan.range_max = float(config.range_max);
  return {f.stamp_ns, order, "/ground_truth/vrs", std::move(scan)};
}

OutMessage artefactImage(const SimFrame& f, const Sensor& camera, int order) {
  const auto& spec = std::get<DepthCameraSpec>(camera.spec);
  msg::Image img;
  img.header = {msg::fromNs(f.stamp_ns), camera.name + "_optical"};
  img.width = uint32_t(spec.width), img.height = uint32_t(spec.height);
  img.encoding = "mono8";
  img.step = img.width;
  img.data.assign(f.artefacts.begin(), f.artefacts.end());
  img.data.resize(size_t(spec.width) * size_t(spec.height), 0);
  return {f.stamp_ns, order, "/depth/" + camera.name + "/artefacts", std::move(img)};
}

}  // namespace polyloc::detail
