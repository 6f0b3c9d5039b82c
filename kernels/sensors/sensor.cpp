#include <polyloc/sensors/sensor.hpp>

#include <stdexcept>

namespace polyloc {

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};

BeamSet Sensor::beams() const {
  return std::visit([](const auto& s) { return s.beams(); }, spec);
}

double Sensor::rateHz() const {
  return std::visit([](const auto& s) { return s.rate_hz; }, spec);
}

const char* Sensor::typeName() const {
  return std::visit(Overloaded{[](const PlanarScannerSpec&) { return "planar_scanner"; },
                               [](const LidarSpec&) { return "lidar"; },
                               [](const DepthCameraSpec&) { return "depth_camera"; }},
                    spec);
}

std::vector<std::string> sensorPresetNames() {
  return {"sick_s300", "hokuyo_urg04lx", "sick_lms200", "vlp16", "pmd_o3d100", "recorded"};
}

SensorSpec sensorPreset(const std::string& preset) {
  if (preset == "sick_s300") return sickS300();
  if (preset == "hokuyo_urg04lx") return hokuyoURG04LX();
  if (preset == "sick_lms200") return sickLMS200();
  if (preset == "vlp16") return velodyneVLP16();
  if (preset == "pmd_o3d100") return pmdO3D100();
  if (preset == "recorded") {  // a planar scanner whose geometry the recording gives
    PlanarScannerSpec p;
    p.from_recording = true;
    return p;
  }
  std::string known;
  for (const auto& n : sensorPresetNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown sensor preset '" + preset + "' (known: " + known + ")");
}

}  // namespace polyloc
