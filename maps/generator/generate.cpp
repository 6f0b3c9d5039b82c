#include <polyloc/mapgen/generate.hpp>

#include <stdexcept>

namespace polyloc {

Mesh generateMap(const std::string& name, MapLayout* layout) {
  if (name == "lab") return generateLab({}, layout);
  if (name == "office") return generateOffice({}, layout);
  throw std::invalid_argument("unknown map '" + name + "': expected lab or office");
}

const std::vector<std::string>& generatedMapNames() {
  static const std::vector<std::string> names{"lab", "office"};
  return names;
}

}  // namespace polyloc
