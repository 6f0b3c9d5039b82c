#include <polyloc/mcl/weighing.hpp>
#include <polyloc/raycast/factory.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace polyloc {

std::vector<uint8_t> weighedSensors(const Rig& rig, const MclConfig& config) {
  std::vector<uint8_t> on(rig.size(), config.sensors.empty() ? 1 : 0);
  for (const std::string& name : config.sensors) {
    const int i = rig.find(name);
    if (i < 0) throw std::invalid_argument("mcl: sensor '" + name + "' is not in rig '" + rig.name + "'");
    on[size_t(i)] = 1;
  }
  // A 2D grid answers every ray with the slice (no floor, no table tops): only level scanners
  // see what it holds. Listing another is a mistake worth an error, not silent wrong weights.
  if (config.caster == "grid2d")
    for (size_t i = 0; i < rig.size(); ++i)
      if (on[i] && !rig.isLevelScanner(i)) {
        if (!config.sensors.empty())
          throw std::invalid_argument("mcl: caster grid2d weighs level planar scanners only; sensor '" +
                                      rig.sensors[i].name + "' is a tilted scanner or not a planar scanner");
        on[i] = 0;  // sensors unset: the level scanners
      }
  if (std::find(on.begin(), on.end(), uint8_t{1}) == on.end())
    throw std::invalid_argument("mcl: no sensor of rig '" + rig.name + "' is weighed" +
                                (config.caster == "grid2d" ? std::string(" (grid2d needs a level planar scanner)") : ""));
  return on;
}

double weighingSliceHeight(const Rig& rig, const MclConfig& config) {
  if (std::isfinite(config.caster_height)) return config.caster_height;
  const std::vector<uint8_t> on = weighedSensors(rig, config);
  double z = INFINITY;
  for (size_t i = 0; i < rig.size(); ++i)
    if (on[i] && rig.isLevelScanner(i)) z = std::min(z, rig.sensors[i].mount.z());
  return std::isfinite(z) ? z : 0.3;
}

std::unique_ptr<RayCaster> makeWeighingCaster(const Mesh& mesh, const Rig& rig, const MclConfig& config,
                                              int threads) {
  if (config.caster == "embree") return nullptr;
  CasterOptions o;
  o.threads = threads;
  o.resolution = config.caster_resolution;
  o.height = weighingSliceHeight(rig, config);
  o.gpu_platforms = config.gpu_platforms;
  o.gpu_fallback = config.gpu_fallback == "embree";
  return makeCaster(config.caster, mesh, o);
}

}  // namespace polyloc
