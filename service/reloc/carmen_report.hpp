// How `polyloc eval carmen` reports its result (reloc/carmen_eval.hpp): the JSON object, the
// text table of the robustness matrix, the strips picture (viz/error_strips.hpp) and the map
// picture with the paths and the global starts.
#pragma once

#include "reloc/carmen_eval.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace polyloc::reloc {

// Frames farther than this from the truth: "beyond" in the table and the JSON.
inline constexpr double kCarmenLostM = 0.5;

nlohmann::json carmenCaseJson(const CarmenCase& c, const CarmenEvalResult& r);
nlohmann::json carmenMapJson(const CarmenMap& m, const CarmenEvalResult& r, const CarmenEvalOptions& o);
nlohmann::json carmenJson(const CarmenEvalResult& r, const CarmenEvalOptions& o);

// The summary lines and the matrix table (fixed-width text).
std::string carmenText(const CarmenEvalResult& r, const CarmenEvalOptions& o);

// Rows map style x decimation, columns odometry (viz/error_strips.hpp).
void drawCarmenStrips(const CarmenEvalResult& r, const std::string& png_path);

// The first map style's slice, the truth, the first drift case's and the own case's estimates,
// the first drift's odometry alone, the global starts (green: succeeded).
void drawCarmenPlot(const CarmenEvalResult& r, const CarmenEvalOptions& o, const std::string& png_path);

}  // namespace polyloc::reloc
