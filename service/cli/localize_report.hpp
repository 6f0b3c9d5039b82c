// How `polyloc localize` reports accuracy: trajectory metrics as JSON (NaN -> null) and the
// per-frame CSV (docs/localization.md).
#pragma once

#include <polyloc/eval/trajectory_metrics.hpp>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace polyloc::cli {

nlohmann::json num(double x);  // null when not finite
nlohmann::json summaryJson(const ErrorSummary& s);
// With metrics: per evaluated frame, estimate, ground truth and errors; without: the estimates.
// Throws std::runtime_error naming the file when it cannot be written.
void writeCsv(const std::string& path, const TrajectoryMetrics* metrics, const std::vector<EstimatedPose>& est);

}  // namespace polyloc::cli
