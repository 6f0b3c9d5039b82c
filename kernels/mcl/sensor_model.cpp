// The model factory: one place that knows every sibling model by its config name.
#include <polyloc/mcl/beam_model.hpp>
#include <polyloc/mcl/depth_model.hpp>
#include <polyloc/mcl/likelihood_field.hpp>
#include <polyloc/mcl/plane_fragments.hpp>
#include <polyloc/mcl/sensor_model.hpp>

#include <stdexcept>

namespace polyloc {

const std::vector<std::string>& sensorModelNames() {
  static const std::vector<std::string> names = {"beam", "likelihood_field", "plane_fragments", "depth"};
  return names;
}

std::unique_ptr<SensorModel> makeSensorModel(const std::string& name, const RayCaster& caster,
                                             const Mesh& map, const Rig& rig, const MclConfig& config) {
  if (name == "beam") return std::make_unique<BeamSensorModel>(caster, rig, config);
  if (name == "depth") return std::make_unique<DepthSensorModel>(caster, rig, config);
  if (name == "likelihood_field") return std::make_unique<LikelihoodFieldModel>(map, rig, config);
  if (name == "plane_fragments") return std::make_unique<PlaneFragmentModel>(caster, rig, config);
  std::string known;
  for (const auto& n : sensorModelNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown measurement model '" + name + "' (known: " + known + ")");
}

}  // namespace polyloc
