// The bundled maps by name, with default options: what `polyloc map generate NAME` writes.
#pragma once

#include <polyloc/map/mesh.hpp>
#include <polyloc/mapgen/lab.hpp>
#include <polyloc/mapgen/office.hpp>

#include <string>
#include <vector>

namespace polyloc {

// "lab" or "office"; throws std::invalid_argument("unknown map 'x': expected lab or office").
Mesh generateMap(const std::string& name, MapLayout* layout = nullptr);
const std::vector<std::string>& generatedMapNames();

}  // namespace polyloc
