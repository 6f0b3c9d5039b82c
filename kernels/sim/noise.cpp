#include <polyloc/sim/noise.hpp>

#include <algorithm>
#include <stdexcept>

namespace polyloc {

GlassMode parseGlassMode(const std::string& s) {
  if (s == "transparent") return GlassMode::Transparent;
  if (s == "mirror") return GlassMode::Mirror;
  if (s == "opaque") return GlassMode::Opaque;
  throw std::invalid_argument("unknown glass mode '" + s + "' (transparent, mirror, opaque)");
}

const char* glassModeName(GlassMode m) {
  switch (m) {
    case GlassMode::Transparent: return "transparent";
    case GlassMode::Mirror: return "mirror";
    default: return "opaque";
  }
}

double SensorNoise::sigmaAt(double r) const { return std::max(sigma + sigma_slope * r, sigma_rel * r); }

// Sources and reasoning in docs/simulation.md ("Noise defaults").
SensorNoise defaultNoise(const std::string& preset, const SensorSpec& spec) {
  SensorNoise n;
  n.specular_labels.clear();  // reflection outliers are a ToF effect by default
  if (preset == "sick_s300") {
    n.sigma = 0.03, n.dropout = 0.002, n.max_range = 0.001;
  } else if (preset == "hokuyo_urg04lx") {
    n.sigma = 0.01, n.sigma_rel = 0.01, n.dropout = 0.005, n.max_range = 0.002;
  } else if (preset == "sick_lms200") {
    n.sigma = 0.005, n.dropout = 0.001, n.max_range = 0.001;
  } else if (preset == "vlp16") {
    n.sigma = 0.03, n.dropout = 0.002;
  } else if (preset == "pmd_o3d100" || std::holds_alternative<DepthCameraSpec>(spec)) {
    n.sigma = 0.002, n.sigma_slope = 0.0008, n.dropout = 0.001;
    n.flying_pixel = 0.5, n.flying_threshold = 0.2;
    n.reflection_outlier = 0.05, n.specular_labels = {"glass", "cabinet", "door"};
  } else if (std::holds_alternative<LidarSpec>(spec)) {
    n.sigma = 0.03, n.dropout = 0.002;
  } else {
    n.sigma = 0.01, n.dropout = 0.002, n.max_range = 0.001;
  }
  return n;
}

double defaultReflectivity(const std::string& label) {
  static const std::map<std::string, double> table{
      {"wall", 0.8},  {"floor", 0.4},  {"glass", 0.1},   {"door", 0.6},  {"table", 0.5},
      {"chair", 0.3}, {"shelf", 0.6},  {"cabinet", 0.7}, {"bin", 0.5},   {"danger", 0.6},
      {"ramp", 0.4},  {"person", 0.5}, {"ceiling", 0.8}};
  const auto it = table.find(label);
  return it == table.end() ? 0.5 : it->second;
}

}  // namespace polyloc
