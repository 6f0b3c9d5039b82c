// The localisation part of `polyloc bench maps`: a scenario simulated (sensors from the exact
// Embree caster of the simulator) while a Localizer weighs its particles with the backend under
// test, started at the true pose; accuracy of the estimates and speed of the localiser. grid2d
// weighs the level scanners only and is sliced at the lowest one's height (mcl/weighing.hpp).
#pragma once

#include <polyloc/raycast/factory.hpp>

#include <nlohmann/json.hpp>
#include <string>

namespace polyloc::cli {

struct BenchLocalizeArgs {
  std::string scenario;   // scenario YAML
  double duration = 30;   // s simulated
  size_t particles = 0;   // 0 = the scenario config's
  bool level_scanners = false;  // every backend weighs the level scanners only (grid2d always does)
};

// JSON: {sensors, slice_height_m, updates, localizer_s, updates_per_s, trans_err_mean_m,
// trans_err_p95_m, yaw_err_mean_deg, final_status, sim_duration_s}. Throws what the scenario loader throws.
nlohmann::json benchLocalize(const std::string& backend, const CasterOptions& options,
                             const BenchLocalizeArgs& args);

}  // namespace polyloc::cli
